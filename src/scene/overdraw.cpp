// The overdraw analyzers: what a frame shades (analyze_overdraw, a software
// rasterizer modelled on meshoptimizer's meshopt_analyzeOverdraw) and the
// least it could shade (ideal_overdraw). analyze_overdraw is the one
// triangle rasterizer in depthcull: the cost model's frame_features reads
// its fragment counts too, as meshoptimizer's one rasterizer serves both
// meshopt_analyzeOverdraw and meshopt_analyzeCoverage. Paper 3 measured overdraw by
// drawing untextured polygons with additive blending; counting on the CPU
// gives the same figure without a GPU, per pixel, for tests and heatmaps.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "depthcull/overdraw.h"

namespace depthcull {

namespace {

// llvmpipe snaps vertices to 1/256 pixel (FIXED_ORDER 8) before it
// evaluates edge functions in integers; doing the same makes coverage on
// an edge through a pixel centre come out as it does there, not as
// floating-point noise decides.
constexpr int kSubpixelBits = 8;
constexpr double kSubpixel = 1 << kSubpixelBits;
// A triangle with a vertex beyond this many pixels (7.0e13) from the
// viewport's corner is skipped, though GL would clip it to what is in view:
// a sprite's corner within limits.h's bounds (transform numbers up to 1e9,
// images up to 16384 px) lies within 3.3e13, and 128-bit edge values hold
// this (2^54 subpixels, products under 2^111).
constexpr double kMaxCoordinate = double(std::int64_t(1) << 46);
// Edge values (products of two subpixel coordinates) fit 64 bits while
// every vertex lies within this many pixels of the viewport's corner
// (2 * (2^22 * 2^8)^2 = 2^61); a triangle reaching further (a sprite scaled
// or placed far out, still in view) is evaluated in 128 bits.
constexpr double kNarrowCoordinate = double(1 << 22);
__extension__ typedef __int128 Wide; // GCC and Clang, wasm32 included

struct Fixed {
    std::int64_t x, y;
};

// A point (pixels from the viewport's corner) snapped as llvmpipe snaps a
// vertex; false beyond kMaxCoordinate, where the rasterizer skips it.
bool snap(double x, double y, Fixed* out) {
    if (!(std::abs(x) < kMaxCoordinate && std::abs(y) < kMaxCoordinate)) return false;
    *out = {std::llround(x * kSubpixel), std::llround(y * kSubpixel)};
    return true;
}

// Which pixel centres exactly on an edge belong to the triangle, so a
// pixel on an edge two triangles share is shaded once. Edges are oriented
// so the interior is on the positive side; with window y growing down the
// rows, llvmpipe keeps centres on "top" edges (horizontal, interior below,
// dx > 0) and "left" edges (dy < 0). tests/render checks this against
// GL_SAMPLES_PASSED. Exact for triangles inside the viewport; GL clips
// those that cross its edge, and a centre exactly on a clipped edge may
// then fall either way.
bool owns_ties(Fixed a, Fixed b) {
    std::int64_t dx = b.x - a.x, dy = b.y - a.y;
    return dy < 0 || (dy == 0 && dx > 0);
}

// T: std::int64_t, or Wide where coordinates pass kNarrowCoordinate.
template <class T>
struct EdgeOf {
    T a, b, c; // E(x, y) = a*x + b*y + c, in subpixel units squared
    T bias;    // 0 when ties count as inside, else 1

    EdgeOf(Fixed p, Fixed q) {
        a = -(T(q.y) - T(p.y));
        b = T(q.x) - T(p.x);
        c = -(a * T(p.x) + b * T(p.y));
        bias = owns_ties(p, q) ? 0 : 1;
    }
    T at(T x, T y) const { return a * x + b * y + c; }
};

// The 4x4 pixel blocks (aligned to the framebuffer's origin) one triangle
// covers a pixel centre of: llvmpipe shades whole blocks, so a block an
// edge crosses costs what a full one does (issue 25's measurements,
// docs/ideal-frame.md section 9). A triangle's covered pixels in a row are
// one run; the runs of the four rows of a block row are merged.
class BlockRows {
public:
    void add_row(int py, int first, int last) {
        if (py >> 2 != row_) {
            flush();
            row_ = py >> 2;
        }
        runs_[n_++] = {first >> 2, last >> 2};
    }
    std::int64_t total() {
        flush();
        return total_;
    }

private:
    void flush() {
        // At most four runs: an insertion sort (std::sort trips gcc 12's
        // -Warray-bounds on so small an array).
        for (int i = 1; i < n_; ++i)
            for (int j = i; j > 0 && runs_[j] < runs_[j - 1]; --j) std::swap(runs_[j], runs_[j - 1]);
        int end = -1; // last block column counted in this block row
        for (int i = 0; i < n_; ++i) {
            const int lo = std::max(runs_[i].first, end + 1);
            if (runs_[i].second >= lo) total_ += runs_[i].second - lo + 1;
            end = std::max(end, runs_[i].second);
        }
        n_ = 0;
    }
    std::pair<int, int> runs_[4];
    int n_ = 0, row_ = -1;
    std::int64_t total_ = 0;
};

std::uint32_t depth24(double z) {
    z = std::clamp(z, 0.0, 1.0);
    return std::uint32_t(std::lround(z * 16777215.0));
}

// Whether an element drawn with `blend` and colour alpha `colour_alpha`
// hides what is behind it where its texel is fully opaque (the ideal
// frame's rule, for elements and for the meshes' fragments alike).
bool can_cover(Blend blend, double colour_alpha) { return (blend == Blend::alpha && colour_alpha >= 1.0) || blend == Blend::opaque; }

// One covered pixel centre of a triangle: the vertices (after orienting
// it), each one's barycentric weight times `area` (the edge values), and
// whether it passed the depth test.
struct Fragment {
    const Draw* draw;
    std::size_t triangle; // 1, 2, ... in the order drawn
    std::size_t pixel;
    const float* vertex[3];
    double weight[3], area; // exact below 2^53, as close as doubles get beyond
    bool shaded;
    // A vertex attribute (kVertexFloats index) at the centre.
    double attribute(int a) const { return (weight[0] * vertex[0][a] + weight[1] * vertex[1][a] + weight[2] * vertex[2][a]) / area; }
};

// floor(n / d) for d > 0 (C++ division truncates towards zero).
template <class T>
T floor_div(T n, T d) {
    const T q = n / d;
    return n % d != 0 && n < 0 ? q - 1 : q;
}

// Narrows [lo, hi], the columns k (0 ..) of a row whose centres lie inside,
// to those where one edge's value w + a * k is at least its bias: a
// half-plane meets a row in a ray, so the test per pixel becomes one
// division per row, in the same integers.
template <class T>
void narrow_to_edge(T w, T a, T bias, std::int64_t& lo, std::int64_t& hi) {
    if (a == 0) {
        if (w < bias) hi = lo - 1; // the row lies outside this edge
    } else if (a > 0) {
        const T k = -floor_div<T>(w - bias, a); // ceil((bias - w) / a)
        if (k > T(lo)) lo = k > T(hi) ? hi + 1 : std::int64_t(k);
    } else {
        const T k = floor_div<T>(w - bias, -a);
        if (k < T(hi)) hi = k < T(lo) ? lo - 1 : std::int64_t(k);
    }
}

// Pixels of the viewport, inclusive. Empty when x0 > x1 or y0 > y1.
struct PixelBox {
    int x0, y0, x1, y1;
};

// The viewport's pixels whose centres lie in the box [x0, x1] x [y0, y1]
// (pixels from the viewport's corner), clamped before they become ints: a
// far coordinate lies outside int's range; NaN gives none.
PixelBox centres_in(double x0, double y0, double x1, double y1, int width, int height) {
    auto to_int = [](double v, int size) { return v >= -1.0 ? (v <= double(size) ? int(v) : size) : -1; };
    return {std::max(0, to_int(std::floor(x0 - 0.5), width)), std::max(0, to_int(std::floor(y0 - 0.5), height)),
            std::min(width - 1, to_int(std::ceil(x1 - 0.5), width)), std::min(height - 1, to_int(std::ceil(y1 - 0.5), height))};
}

// The pixels whose centres a triangle may cover: its snapped vertices' box.
[[gnu::always_inline]] inline PixelBox pixel_box(const Fixed p[3], int width, int height) {
    return centres_in(double(std::min({p[0].x, p[1].x, p[2].x})) / kSubpixel, double(std::min({p[0].y, p[1].y, p[2].y})) / kSubpixel,
                      double(std::max({p[0].x, p[1].x, p[2].x})) / kSubpixel, double(std::max({p[0].y, p[1].y, p[2].y})) / kSubpixel, width,
                      height);
}

// The depth buffer, cleared to 0, over only the box the frame's triangles
// reach (every read and write lands in it), one band of its rows at a time
// when the box is large (kDepthBandPixels): the cost model rasterizes every
// contestant frame (optimize --target) in a viewport that may be a whole
// map of up to 16384^2 px, where a buffer for all of it cost 1 GiB and its
// clearing each time.
struct DepthBuffer {
    PixelBox box{0, 0, -1, -1};
    std::vector<std::uint32_t> depth;
    // The depths of row py from column x (both inside the box).
    std::uint32_t* at(int x, int py) {
        return depth.data() + std::size_t(py - box.y0) * std::size_t(box.x1 - box.x0 + 1) + std::size_t(x - box.x0);
    }
};

// One triangle of rasterize_meshes (which see), its edge values in T.
template <class T, bool kRows, bool kPixels, class OnFragment, class OnRow>
void rasterize_triangle(const SceneMeshes& meshes, const Draw& draw, std::size_t triangle, Fixed p[3], double z[3], const float* vertex[3],
                        DepthBuffer& depth, int band_y0, int band_y1, OnFragment& on_fragment, OnRow& on_row) {
    const int width = std::max(meshes.viewport.width, 0), height = std::max(meshes.viewport.height, 0);
    const bool write_depth = meshes.depth_test && draw.pass == Pass::opaque;
    T area = EdgeOf<T>(p[0], p[1]).at(p[2].x, p[2].y);
    if (area == 0) return; // degenerate: GL draws nothing
    if (area < 0) {
        std::swap(p[1], p[2]);
        std::swap(z[1], z[2]);
        std::swap(vertex[1], vertex[2]);
        area = -area;
    }
    // Edge k is opposite vertex k, so its value is vertex k's barycentric weight.
    const EdgeOf<T> e[3] = {EdgeOf<T>(p[1], p[2]), EdgeOf<T>(p[2], p[0]), EdgeOf<T>(p[0], p[1])};
    const auto [x0, box_y0, x1, box_y1] = pixel_box(p, width, height);
    const int y0 = std::max(box_y0, band_y0), y1 = std::min(box_y1, band_y1); // the rows of this band
    const bool flat = z[0] == z[1] && z[1] == z[2];
    const std::uint32_t flat_depth = depth24(z[0]);
    // Edge values step by a (one pixel right, in subpixel units) from the
    // row's first centre: the same integers as evaluating each centre
    // afresh. Each row's covered centres are one run (three half-planes
    // meet a line in an interval), found by division, so the pixels outside
    // the triangle in its box cost nothing and a caller counting runs
    // (kPixels false) pays per row, not per pixel: the cost model
    // rasterizes every contestant frame through here.
    const T step = 1 << kSubpixelBits;
    const T cx0 = T(x0) * step + step / 2;
    const T a[3] = {e[0].a * step, e[1].a * step, e[2].a * step};
    Fragment f{&draw, triangle, 0, {vertex[0], vertex[1], vertex[2]}, {0, 0, 0}, double(area), true};
    for (int py = y0; py <= y1; ++py) {
        const T cy = T(py) * step + step / 2;
        T w[3] = {e[0].at(cx0, cy), e[1].at(cx0, cy), e[2].at(cx0, cy)};
        std::int64_t first = 0, last = std::int64_t(x1) - x0;
        for (int k = 0; k < 3; ++k) narrow_to_edge<T>(w[k], a[k], e[k].bias, first, last);
        if (first > last) continue;
        // Per pixel only for on_fragment or the depth test: without either,
        // every centre of the run passes.
        std::int64_t passed = last - first + 1;
        if (kPixels || meshes.depth_test) {
            passed = 0;
            for (int k = 0; k < 3; ++k) w[k] += a[k] * T(first);
            const std::size_t row = std::size_t(py) * std::size_t(width) + std::size_t(x0);
            std::uint32_t* stored = meshes.depth_test ? depth.at(x0, py) : nullptr; // from column x0
            // A flat triangle's run without fragments to report (the cost
            // model's usual case) needs no edge values, only its one depth.
            if (!kPixels && flat) {
                for (std::int64_t px = first; px <= last; ++px)
                    if (flat_depth > stored[px]) { // GL_GREATER against a buffer cleared to 0
                        ++passed;
                        if (write_depth) stored[px] = flat_depth;
                    }
            } else {
                for (std::int64_t px = first; px <= last; ++px, w[0] += a[0], w[1] += a[1], w[2] += a[2]) {
                    const std::size_t pixel = row + std::size_t(px);
                    bool shaded = true;
                    if (meshes.depth_test) {
                        const std::uint32_t d =
                            flat ? flat_depth : depth24((double(w[0]) * z[0] + double(w[1]) * z[1] + double(w[2]) * z[2]) / f.area);
                        if (d <= stored[px])
                            shaded = false; // GL_GREATER against a buffer cleared to 0
                        else if (write_depth)
                            stored[px] = d;
                    }
                    passed += shaded;
                    if constexpr (kPixels) {
                        f.pixel = pixel;
                        f.weight[0] = double(w[0]);
                        f.weight[1] = double(w[1]);
                        f.weight[2] = double(w[2]);
                        f.shaded = shaded;
                        on_fragment(f);
                    }
                }
            }
        }
        if constexpr (kRows) on_row(draw, triangle, py, x0 + int(first), int(last - first + 1), int(passed));
    }
}

// One triangle as rasterize_triangle takes it: its vertices snapped, their
// z and attributes, and whether its edge values fit 64 bits.
struct SnappedTriangle {
    Fixed p[3];
    double z[3];
    const float* vertex[3];
    bool narrow;
};

// Triangle t of `draw` (its first index), snapped; false when GL would not
// draw it here (an index past the vertices, a vertex beyond kMaxCoordinate).
[[gnu::always_inline]] inline bool triangle_at(const SceneMeshes& meshes, const Draw& draw, std::size_t t, SnappedTriangle* out) {
    out->narrow = true;
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t i = draw.indices[t + std::size_t(k)];
        if (i >= draw.vertex_count()) return false;
        const float* v = &draw.vertices[std::size_t(i) * kVertexFloats];
        const double x = double(v[0]) - meshes.viewport.x, y = double(v[1]) - meshes.viewport.y;
        if (!snap(x, y, &out->p[k])) return false;
        out->narrow = out->narrow && std::abs(x) < kNarrowCoordinate && std::abs(y) < kNarrowCoordinate;
        out->z[k] = v[2];
        out->vertex[k] = v;
    }
    return true;
}

// The depth buffer over the centres in the box of every vertex of `meshes`
// grown by a pixel, which holds every triangle's pixel_box. A vertex too far
// out to be drawn (snap) only makes the box larger, never wrong; min and
// max skip NaN, and no vertex at all leaves the box empty.
PixelBox depth_box_for(const SceneMeshes& meshes, int width, int height) {
    float fx0 = INFINITY, fy0 = INFINITY, fx1 = -INFINITY, fy1 = -INFINITY;
    for (const Draw& draw : meshes.draws)
        for (std::size_t v = 0; v + kVertexFloats <= draw.vertices.size(); v += kVertexFloats) {
            fx0 = std::min(fx0, draw.vertices[v]), fx1 = std::max(fx1, draw.vertices[v]);
            fy0 = std::min(fy0, draw.vertices[v + 1]), fy1 = std::max(fy1, draw.vertices[v + 1]);
        }
    // A pixel wider on every side: snapping moves a vertex by up to 1/512 px.
    return centres_in(double(fx0) - meshes.viewport.x - 1, double(fy0) - meshes.viewport.y - 1, double(fx1) - meshes.viewport.x + 1,
                      double(fy1) - meshes.viewport.y + 1, width, height);
}

// The most depth values held at once (16 MiB). A larger depth-tested frame
// is rasterized a band of rows at a time, every triangle in order within
// each band: the cost model rasterizes each contestant frame of optimize
// --target in the scene's viewport, up to 16384^2 px, where one buffer for
// all of it took 1 GiB per frame (per plan weighed at once) and the time to
// clear it. Each pixel still meets its fragments in drawing order, so every
// depth test, count and per-pixel result is the same; bands start on block
// rows (multiples of 4), so a triangle's blocks (BlockRows, one triangle at
// a time) split between bands at a block row and add up the same.
constexpr std::size_t kDepthBandPixels = std::size_t(1) << 22;

// Rasterizes every triangle of `meshes` the way GL does (see
// analyze_overdraw), the depth test included: on_fragment(const Fragment&)
// for each covered centre (kPixels), on_row(const Draw&, triangle, py,
// first, count, passed) after each row of a triangle that covers `count`
// centres from column `first`, `passed` of them passing the depth test
// (kRows; `triangle` counts the triangles rasterized, to tell them apart).
template <bool kRows, bool kPixels, class OnFragment, class OnRow>
void rasterize_meshes(const SceneMeshes& meshes, OnFragment&& on_fragment, OnRow&& on_row) {
    const int width = std::max(meshes.viewport.width, 0), height = std::max(meshes.viewport.height, 0);
    // Rows first_row .. last_row, `band` at a time: the box the depth
    // buffer needs (empty: no triangle covers a centre), else the viewport.
    int first_row = 0, last_row = height - 1, band = std::max(height, 1);
    PixelBox box{0, 0, width - 1, height - 1};
    if (meshes.depth_test) {
        box = depth_box_for(meshes, width, height);
        first_row = box.y0 / 4 * 4; // bands start on block rows
        last_row = box.x0 <= box.x1 && box.y0 <= box.y1 ? box.y1 : -1;
        const std::size_t columns = std::size_t(std::max(box.x1 - box.x0 + 1, 1)), span = std::size_t(std::max(last_row - first_row + 1, 1));
        band = int(span);
        if (columns * span > kDepthBandPixels) band = int(std::max<std::size_t>(4, kDepthBandPixels / columns / 4 * 4));
    }
    // With several bands, each triangle's rows first (first -1 for one GL
    // would not draw, which is not numbered; pixel_box's rows are never
    // negative), so a band passes over the others without snapping them.
    const bool banded = last_row - first_row + 1 > band;
    std::vector<std::pair<int, int>> rows;
    if (banded)
        for (const Draw& draw : meshes.draws)
            for (std::size_t t = 0; t + 3 <= draw.indices.size(); t += 3) {
                SnappedTriangle s;
                const PixelBox b = triangle_at(meshes, draw, t, &s) ? pixel_box(s.p, width, height) : PixelBox{-1, -1, -1, -1};
                rows.push_back({b.y0, b.y1});
            }
    DepthBuffer depth;
    for (int band_y0 = first_row; band_y0 <= last_row; band_y0 += band) {
        const int band_y1 = std::min(band_y0 + band - 1, last_row);
        if (meshes.depth_test) {
            depth.box = {box.x0, std::max(band_y0, box.y0), box.x1, band_y1};
            depth.depth.assign(std::size_t(box.x1 - box.x0 + 1) * std::size_t(depth.box.y1 - depth.box.y0 + 1), 0);
        }
        std::size_t triangle = 0, k = 0; // triangles drawn, triangles
        for (const Draw& draw : meshes.draws)
            for (std::size_t t = 0; t + 3 <= draw.indices.size(); t += 3, ++k) {
                SnappedTriangle s;
                if (banded) {
                    if (rows[k].first < 0) continue;
                    ++triangle;
                    if (rows[k].second < band_y0 || rows[k].first > band_y1) continue;
                    triangle_at(meshes, draw, t, &s);
                } else if (triangle_at(meshes, draw, t, &s)) {
                    ++triangle;
                } else {
                    continue;
                }
                if (s.narrow)
                    rasterize_triangle<std::int64_t, kRows, kPixels>(meshes, draw, triangle, s.p, s.z, s.vertex, depth, band_y0, band_y1,
                                                                     on_fragment, on_row);
                else
                    rasterize_triangle<Wide, kRows, kPixels>(meshes, draw, triangle, s.p, s.z, s.vertex, depth, band_y0, band_y1, on_fragment,
                                                             on_row);
            }
    }
}

} // namespace

OverdrawStats analyze_overdraw(const SceneMeshes& meshes, OverdrawMap* map, bool count_blocks) {
    const int width = std::max(meshes.viewport.width, 0), height = std::max(meshes.viewport.height, 0);
    OverdrawStats stats;
    stats.pixels = std::int64_t(width) * height;
    // Per-pixel counts only for a map: a 16k x 16k viewport would spend 1 GB on them.
    std::vector<std::uint32_t> counts(map ? std::size_t(stats.pixels) : 0, 0);
    BlockRows blocks;
    const Draw* block_draw = nullptr;
    std::size_t block_triangle = 0;
    auto flush_blocks = [&] {
        if (block_draw) (block_draw->pass == Pass::opaque ? stats.blocks_opaque : stats.blocks_blend) += blocks.total();
        blocks = BlockRows();
        block_draw = nullptr;
    };
    auto on_fragment = [&](const Fragment& f) {
        ++stats.rasterized;
        if (!f.shaded) return;
        if (map) ++counts[f.pixel];
        ++stats.shaded;
        if (f.draw->pass == Pass::opaque) ++stats.shaded_opaque;
    };
    auto on_row = [&](const Draw& draw, std::size_t triangle, int py, int first, int count, int) {
        if (triangle != block_triangle) flush_blocks(); // blocks are counted per triangle
        block_draw = &draw;
        block_triangle = triangle;
        blocks.add_row(py, first, first + count - 1);
    };
    // Without a map the counts are the rows' runs: no work per pixel but the
    // depth test's.
    auto on_run = [&](const Draw& draw, std::size_t triangle, int py, int first, int count, int passed) {
        stats.rasterized += count;
        stats.shaded += passed;
        if (draw.pass == Pass::opaque) stats.shaded_opaque += passed;
        if (count_blocks) on_row(draw, triangle, py, first, count, passed);
    };
    if (!map)
        rasterize_meshes<true, false>(meshes, on_fragment, on_run);
    else if (count_blocks)
        rasterize_meshes<true, true>(meshes, on_fragment, on_row);
    else
        rasterize_meshes<false, true>(meshes, on_fragment, on_row);
    flush_blocks();
    if (map) {
        map->width = width;
        map->height = height;
        map->counts = std::move(counts);
    }
    return stats;
}

ExcessStats excess_overdraw(const SceneMeshes& meshes, const std::vector<ImageView>& images) {
    const int width = std::max(meshes.viewport.width, 0), height = std::max(meshes.viewport.height, 0);
    ExcessStats out;
    // Nearness: the depth plan's z where the meshes have depth values (24
    // bits tell every level apart: D <= 2^22), in either pass, with or
    // without the depth test; else the order of drawing (overpaint and
    // meshes only draw what overlaps in painter's order; one element's
    // triangles do not overlap).
    const bool by_z = meshes.depth_denominator > 0;
    auto nearness = [&](const Fragment& f) { return by_z ? std::uint32_t(depth24(f.attribute(2))) : std::uint32_t(f.triangle); };
    // The texel alpha a fragment shows, and whether it hides what is behind
    // (as ideal_overdraw decides: opaque texel, colour alpha 1, alpha blend
    // or Blend::opaque, or any opaque-pass fragment).
    auto texel_alpha = [&](const Fragment& f, bool* covers) {
        const Draw& d = *f.draw;
        const bool opaque_draw = d.pass == Pass::opaque || d.blend == Blend::opaque;
        std::uint8_t alpha = 255;
        if (!opaque_draw && d.image >= 0 && std::size_t(d.image) < images.size()) {
            const ImageView& im = images[std::size_t(d.image)];
            if (im.width > 0 && im.height > 0) {
                const int tx = std::clamp(int(std::floor(f.attribute(3) * im.width)), 0, im.width - 1);
                const int ty = std::clamp(int(std::floor(f.attribute(4) * im.height)), 0, im.height - 1);
                alpha = im.alpha(tx, ty);
            }
        }
        *covers = is_opaque(alpha) && (d.pass == Pass::opaque || can_cover(d.blend, f.attribute(8)));
        return alpha;
    };
    // Per pixel, the nearest fragment that hides what is behind it, plus one
    // (0: none).
    std::vector<std::uint32_t> front(std::size_t(width) * std::size_t(height), 0);
    // Whether that nearest one has been counted: overlapping opaque pieces
    // of one element (grown polygons may overlap) shade a pixel twice where
    // nothing rejects the second (no depth buffer).
    std::vector<std::uint8_t> drawn(front.size(), 0);
    auto no_rows = [](const Draw&, std::size_t, int, int, int, int) {};
    rasterize_meshes<false, true>(
        meshes,
        [&](const Fragment& f) {
            bool covers = false;
            texel_alpha(f, &covers);
            if (covers) front[f.pixel] = std::max(front[f.pixel], nearness(f) + 1);
        },
        no_rows);
    // The blocks of the triangle being walked, one block row at a time (its
    // fragments come row by row): per block column 0 untouched, 1 shaded,
    // 2 shaded with a needed fragment.
    std::vector<std::uint8_t> row_blocks(std::size_t(width / 4 + 1), 0);
    std::vector<std::size_t> touched;
    std::size_t block_triangle = 0, block_row = 0;
    auto flush_blocks = [&] {
        for (std::size_t bx : touched) {
            (row_blocks[bx] == 2 ? out.blocks_needed : out.blocks_waste) += 1;
            row_blocks[bx] = 0;
        }
        touched.clear();
    };
    rasterize_meshes<false, true>(
        meshes,
        [&](const Fragment& f) {
            const std::size_t row = f.pixel / std::size_t(width) / 4, bx = f.pixel % std::size_t(width) / 4;
            if (f.triangle != block_triangle || row != block_row) {
                flush_blocks();
                block_triangle = f.triangle;
                block_row = row;
            }
            std::uint8_t& block = row_blocks[bx];
            if (block == 0) {
                touched.push_back(bx);
                block = 1;
            }
            if (!f.shaded) return;
            bool covers = false;
            const std::uint8_t alpha = texel_alpha(f, &covers);
            const std::uint32_t near = nearness(f) + 1;
            if (is_transparent(alpha))
                ++out.transparent;
            else if (near < front[f.pixel] || (near == front[f.pixel] && covers && drawn[f.pixel]))
                ++out.hidden;
            else {
                ++out.needed;
                block = 2;
                if (covers) drawn[f.pixel] = 1;
            }
        },
        no_rows);
    flush_blocks();
    return out;
}

namespace {

// The pixels whose centres element e's rect may cover on screen: its
// corners' box.
PixelBox element_pixel_box(const Element& e, const Viewport& vp, int width, int height) {
    double bx0 = INFINITY, by0 = INFINITY, bx1 = -INFINITY, by1 = -INFINITY;
    for (Vec2 c : {Vec2{0, 0}, Vec2{double(e.rect.w), 0}, Vec2{0, double(e.rect.h)}, Vec2{double(e.rect.w), double(e.rect.h)}}) {
        const Vec2 s = apply(e.transform, c);
        bx0 = std::min(bx0, s.x - vp.x), by0 = std::min(by0, s.y - vp.y);
        bx1 = std::max(bx1, s.x - vp.x), by1 = std::max(by1, s.y - vp.y);
    }
    return centres_in(bx0, by0, bx1, by1, width, height);
}

} // namespace

OverdrawStats ideal_overdraw(const Scene& scene, const std::vector<ImageView>& images, OverdrawMap* map,
                             std::vector<std::uint8_t>* shows) {
    if (shows) shows->assign(scene.elements.size(), 0);
    const Viewport& vp = scene.viewport;
    const int width = std::max(vp.width, 0), height = std::max(vp.height, 0);
    OverdrawStats stats;
    stats.pixels = std::int64_t(width) * height;
    std::vector<std::uint32_t> counts(map ? std::size_t(stats.pixels) : 0, 0);
    // Set once a pixel has met a fully opaque element: nothing behind it
    // counts. Over the box of what the elements cover only (a whole map's
    // viewport may be 16384^2 px).
    PixelBox drawn{0, 0, -1, -1};
    for (const Element& e : scene.elements) {
        const PixelBox b = element_pixel_box(e, vp, width, height);
        if (b.x0 > b.x1 || b.y0 > b.y1) continue;
        drawn = drawn.x0 > drawn.x1
                    ? b
                    : PixelBox{std::min(drawn.x0, b.x0), std::min(drawn.y0, b.y0), std::max(drawn.x1, b.x1), std::max(drawn.y1, b.y1)};
    }
    const std::size_t drawn_width = drawn.x0 <= drawn.x1 ? std::size_t(drawn.x1 - drawn.x0 + 1) : 0;
    std::vector<std::uint8_t> covered(drawn_width * std::size_t(drawn.x0 <= drawn.x1 ? drawn.y1 - drawn.y0 + 1 : 0), 0);
    // One element's 4x4 blocks over its box, as the ideal frame draws it: its
    // rect as two triangles (split by the diagonal from texel (0, 0) to (w,
    // h)), each shading the blocks it has one of those fragments in. Bits:
    // 1 the first triangle has one there, 2 the second, 4 one of them does
    // not hide what is behind.
    std::vector<std::uint8_t> blocks;

    // Front to back, each element over its screen bounding box only, so the
    // cost is the sum of element areas, not elements * pixels.
    for (std::size_t k = scene.elements.size(); k-- > 0;) {
        const Element& e = scene.elements[k];
        if (e.image < 0 || std::size_t(e.image) >= images.size() || e.rect.empty()) continue;
        if (e.color[3] <= 0.0f) continue; // draws nothing a viewer can see
        const ImageView& image = images[std::size_t(e.image)];
        if (!image.contains(e.rect)) continue;
        const auto& m = e.transform;
        const double det = m[0] * m[3] - m[1] * m[2];
        if (!(det != 0) || !std::isfinite(det)) continue;
        const auto [x0, y0, x1, y1] = element_pixel_box(e, vp, width, height);
        if (x0 > x1 || y0 > y1) continue;
        const bool covers = can_cover(e.blend, e.color[3]);
        // The diagonal as GL rasterizes it (snapped, a centre on it going to
        // the triangle whose top or left edge it is), oriented so the
        // triangle of corners (0, 0), (w, 0), (w, h) lies on its positive
        // side. Corners beyond where rasterize_meshes skips a triangle (GL
        // would clip it) split by texel coordinates instead, ties to the
        // other one.
        const Vec2 corner0 = apply(m, {0, 0}) - Vec2{vp.x, vp.y}, corner1 = apply(m, {double(e.rect.w), 0}) - Vec2{vp.x, vp.y};
        const Vec2 corner2 = apply(m, {double(e.rect.w), double(e.rect.h)}) - Vec2{vp.x, vp.y};
        Fixed c0{}, c1{}, c2{};
        const bool exact = snap(corner0.x, corner0.y, &c0) && snap(corner1.x, corner1.y, &c1) && snap(corner2.x, corner2.y, &c2);
        EdgeOf<Wide> diagonal(c0, c2);
        if (diagonal.at(c1.x, c1.y) < 0) diagonal = EdgeOf<Wide>(c2, c0);
        const Wide step = 1 << kSubpixelBits;
        const int block_x0 = x0 >> 2, blocks_wide = x1 >= x0 ? (x1 >> 2) - block_x0 + 1 : 0;
        const int block_y0 = y0 >> 2, blocks_high = y1 >= y0 ? (y1 >> 2) - block_y0 + 1 : 0;
        blocks.assign(std::size_t(blocks_wide) * std::size_t(blocks_high), 0);
        for (int py = y0; py <= y1; ++py) {
            for (int px = x0; px <= x1; ++px) {
                const std::size_t pixel = std::size_t(py) * std::size_t(width) + std::size_t(px);
                std::uint8_t& hidden = covered[std::size_t(py - drawn.y0) * drawn_width + std::size_t(px - drawn.x0)];
                if (hidden) continue;
                // Pixel centre back to texel space of the rect (inverse of the SVG matrix).
                const double qx = vp.x + px + 0.5 - m[4], qy = vp.y + py + 0.5 - m[5];
                const double u = (m[3] * qx - m[2] * qy) / det, v = (m[0] * qy - m[1] * qx) / det;
                if (!(u >= 0 && v >= 0 && u < e.rect.w && v < e.rect.h)) continue;
                const int tx = std::min(e.rect.x + int(u), e.rect.x + e.rect.w - 1);
                const int ty = std::min(e.rect.y + int(v), e.rect.y + e.rect.h - 1);
                const std::uint8_t alpha = e.blend == Blend::opaque ? 255 : image.alpha(tx, ty);
                if (is_transparent(alpha)) continue;
                if (map) ++counts[pixel];
                if (shows) (*shows)[k] = 1;
                ++stats.shaded;
                ++stats.rasterized;
                const bool hides = covers && is_opaque(alpha);
                if (hides) hidden = 1;
                std::uint8_t& block = blocks[std::size_t((py >> 2) - block_y0) * std::size_t(blocks_wide) + std::size_t((px >> 2) - block_x0)];
                const bool second = exact ? diagonal.at(Wide(px) * step + step / 2, Wide(py) * step + step / 2) >= diagonal.bias
                                          : u * e.rect.h > v * e.rect.w;
                block |= std::uint8_t((second ? 2 : 1) | (hides ? 0 : 4));
            }
        }
        for (std::uint8_t block : blocks) {
            const int shaded = (block & 1) + ((block >> 1) & 1);
            (block & 4 ? stats.blocks_blend : stats.blocks_opaque) += shaded;
        }
    }
    if (map) {
        map->width = width;
        map->height = height;
        map->counts = std::move(counts);
    }
    return stats;
}

} // namespace depthcull
