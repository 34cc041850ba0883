// FrameAssembler (depthcull/frame.h): moving sprites depth-culled every
// frame. Each sprite follows the rules reconstruction gives an element
// (shapes.cpp), and its vertices are the ones MeshBuilder would make for
// it (the same texel-space polygons, texel skirts and pulled-in opaque
// polygons, transformed the same way), so a frame draws pixel for pixel
// like overpaint in a plain renderer (texel_margin.cpp says why). The one
// difference is cheaper: the skirts take the joined form, welded, where a
// convex polygon and its skirt are one dilated polygon (texel_margin.cpp),
// covering the same points, so a sprite is a template of few vertices that
// a frame only transforms.
//
// Depth: sprite i of a frame (or of an insertion point) gets level
// first + i, one per sprite in painter's order. That needs no graph: each
// sprite is in front of every sprite before it, which is all the painter's
// order asks. The graph is needed only to batch the blend pass: a sprite may
// join an earlier draw of its texture unless it overlaps a sprite drawn in
// between. Overlap is tested on a grid of screen cells holding, per cell,
// the latest batch any sprite there joined; a sprite covering more than
// cell_budget cells counts as overlapping everything, so the work per
// sprite is bounded (batching degrades, correctness never does).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

#include "depthcull/frame.h"
#include "scene/internal.h"
#include "scene/placement.h"

// SSE2 streaming stores for frame vertices (x86-64 always has SSE2);
// elsewhere (WebAssembly, ARM) plain stores.
#if defined(__SSE2__) && !defined(__EMSCRIPTEN__)
#include <emmintrin.h>
#define DEPTHCULL_STREAM_VERTICES 1
#else
#define DEPTHCULL_STREAM_VERTICES 0
#endif

namespace {
// Frames whose vertices take more than this stream them past the caches
// (FrameAssembler::emit); smaller ones stay cached for the upload.
constexpr std::size_t kStreamBytes = std::size_t(8) << 20;
} // namespace

namespace depthcull {

using namespace detail;

namespace {

bool finite_sprite(const Sprite& s) {
    for (double v : s.transform)
        if (!std::isfinite(v)) return false;
    for (float c : s.color)
        if (!std::isfinite(c)) return false;
    return true;
}

} // namespace

FrameStatus FrameAssembler::add_image(const SpriteImage& image, int* id) {
    const ImageAnalysis* a = image.analysis;
    if (!id || !a || image.texture < 0 || image.rect.empty() || image.texture_width <= 0 || image.texture_height <= 0 ||
        !ImageView{nullptr, image.texture_width, image.texture_height, 0}.contains(image.rect))
        return FrameStatus::bad_image;
    // A one-element scene for MeshBuilder, capturing texel-space polygons.
    Scene scene;
    scene.images.push_back({"", "", image.texture_width, image.texture_height});
    Element e;
    e.rect = image.rect;
    scene.elements.push_back(e);
    Picture p;
    p.texture = image.texture;
    p.rect = image.rect;
    const double iw = 1.0 / image.texture_width, ih = 1.0 / image.texture_height;
    // Vertices at the same texel position are one vertex (the same
    // position and texture coordinate, so drawn alike).
    auto to_template = [&](const TexelMesh& m, Template& t) {
        std::map<std::pair<double, double>, std::uint32_t> index_of;
        for (std::uint32_t k : m.indices) {
            const Vec2 v = m.points[k];
            auto [it, fresh] = index_of.emplace(std::pair{v.x, v.y}, std::uint32_t(t.xy.size() / 2));
            if (fresh) {
                t.xy.push_back(v.x - image.rect.x);
                t.xy.push_back(v.y - image.rect.y);
                t.uv.push_back(float(v.x * iw));
                t.uv.push_back(float(v.y * ih));
            }
            t.indices.push_back(it->second);
        }
        // Whole groups of 4 vertices (emit's streaming stores), padded with
        // copies of the last one, which no index names.
        while (t.xy.size() % 8 != 0) {
            t.xy.insert(t.xy.end(), {t.xy[t.xy.size() - 2], t.xy[t.xy.size() - 1]});
            t.uv.insert(t.uv.end(), {t.uv[t.uv.size() - 2], t.uv[t.uv.size() - 1]});
        }
    };
    Draw unused;
    p.has_boundary = !a->boundary.empty();
    p.has_opaque = !a->opaque.empty();
    std::size_t most_vertices = 8, most_indices = 12;
    for (int b = 0; b < kMarginBuckets; ++b) {
        const double margin = kTexelMargin * double(1 << b);
        // Boundary polygons with their texel skirt in the joined form
        // (texel_margin.cpp): a convex polygon's skirt is the polygon
        // dilated, which replaces it.
        if (p.has_boundary) {
            TexelMesh skirt, m;
            MeshBuilder skirted(scene, 0, 0, margin);
            skirted.capture(&skirt, true, true);
            skirted.add_texel_skirts(unused, 0, a->boundary, 0);
            for (std::size_t k = 0; k < a->boundary.size(); ++k) {
                if (k < skirted.dilated().size() && skirted.dilated()[k]) continue;
                const auto base = std::uint32_t(m.points.size());
                m.points.insert(m.points.end(), a->boundary[k].begin(), a->boundary[k].end());
                for (std::uint32_t t : triangulate_polygon(a->boundary[k])) m.indices.push_back(base + t);
            }
            const auto base = std::uint32_t(m.points.size());
            m.points.insert(m.points.end(), skirt.points.begin(), skirt.points.end());
            for (std::uint32_t t : skirt.indices) m.indices.push_back(base + t);
            to_template(m, p.boundary[b]);
        }
        if (p.has_opaque) {
            TexelMesh opaque;
            MeshBuilder builder(scene, 0, 0, margin);
            builder.capture(&opaque, true);
            builder.add_opaque(unused, 0, Shape::analysis, a, 0);
            to_template(opaque, p.opaque[b]);
        }
        most_vertices = std::max(most_vertices, p.boundary[b].xy.size() / 2 + p.opaque[b].xy.size() / 2);
        most_indices = std::max(most_indices, p.boundary[b].indices.size() + p.opaque[b].indices.size());
    }
    p.has_opaque = !p.opaque[0].indices.empty();
    if (p.has_boundary) {
        // Without a skirt (transforms that snap exactly), as MeshBuilder draws them.
        TexelMesh m;
        MeshBuilder plain(scene, 0, 0, 0);
        plain.capture(&m, true);
        plain.add_boundary(unused, 0, Shape::analysis, a, 0);
        to_template(m, p.plain);
        most_vertices = std::max(most_vertices, p.plain.xy.size() / 2 + p.opaque[0].xy.size() / 2);
        most_indices = std::max(most_indices, p.plain.indices.size() + p.opaque[0].indices.size());
        p.boundary_inside = true;
        for (const Polygon& poly : a->boundary)
            for (const Vec2& v : poly)
                if (v.x < image.rect.x || v.y < image.rect.y || v.x > double(image.rect.x) + image.rect.w ||
                    v.y > double(image.rect.y) + image.rect.h)
                    p.boundary_inside = false;
    }
    {
        const Polygon r = rect_polygon(image.rect);
        TexelMesh quad{{r.begin(), r.end()}, {0, 1, 2, 0, 2, 3}};
        to_template(quad, p.quad);
    }
    p.bleeding_edges = a->bleeding_edges;
    p.opaque_covers_all = a->stats.nontransparent_texels > 0 && a->stats.opaque_covered_texels == a->stats.nontransparent_texels;
    // The box that holds whatever the sprite draws: its rect (skirts are
    // clipped to it).
    p.bx0 = 0, p.by0 = 0, p.bx1 = image.rect.w, p.by1 = image.rect.h;
    if (p.has_boundary && p.boundary_inside) {
        p.bx0 = p.by0 = INFINITY, p.bx1 = p.by1 = -INFINITY;
        for (const Template& t : p.boundary)
            for (std::size_t k = 0; k + 1 < t.xy.size(); k += 2) {
                p.bx0 = std::min(p.bx0, t.xy[k]), p.bx1 = std::max(p.bx1, t.xy[k]);
                p.by0 = std::min(p.by0, t.xy[k + 1]), p.by1 = std::max(p.by1, t.xy[k + 1]);
            }
    }
    max_vertices_ = std::max(max_vertices_, most_vertices);
    max_indices_ = std::max(max_indices_, most_indices);
    max_texture_ = std::max(max_texture_, image.texture);
    *id = int(images_.size());
    images_.push_back(std::move(p));
    return FrameStatus::ok;
}

FrameStatus FrameAssembler::add_animation(std::span<const int> images, int* id) {
    if (!id || images.empty()) return FrameStatus::bad_image;
    for (int i : images)
        if (i < 0 || std::size_t(i) >= images_.size()) return FrameStatus::bad_image;
    *id = int(animations_.size());
    animations_.emplace_back(images.begin(), images.end());
    return FrameStatus::ok;
}

void FrameAssembler::reserve(std::size_t sprites, AssembledFrame* out) {
    plan_.reserve(sprites);
    batch_key_.reserve(sprites);
    batch_count_.reserve(sprites);
    const std::size_t keys = std::size_t(max_texture_ + 1) * 4;
    last_batch_of_key_.reserve(keys);
    key_count_.reserve(keys);
    key_nearest_.reserve(keys);
    key_order_.reserve(keys);
    cell_top_.reserve(std::size_t(std::max(options_.max_cells, 1)));
    ranges_.reserve(16);
    point_batch_.reserve(17);
    if (out) {
        out->vertices.reserve(sprites * max_vertices_ * kVertexFloats);
        out->indices.reserve(sprites * max_indices_);
        out->draws.reserve(2 * sprites + 1);
        out->points.reserve(16);
    }
}

inline FrameStatus FrameAssembler::plan_sprite(const Sprite& s, Plan& p) {
    int picture = s.image;
    if (s.animation >= 0) {
        if (std::size_t(s.animation) >= animations_.size()) return FrameStatus::bad_sprite;
        const std::vector<int>& frames = animations_[std::size_t(s.animation)];
        const int n = int(frames.size());
        picture = frames[std::size_t(((s.frame % n) + n) % n)];
    }
    if (picture < 0 || std::size_t(picture) >= images_.size() || !finite_sprite(s) || int(s.blend) < 0 || int(s.blend) > 3)
        return FrameStatus::bad_sprite;
    const Picture& pic = images_[std::size_t(picture)];
    p.picture = picture;
    p.key = pic.texture * 4 + int(s.blend);
    p.batch = -1;
    p.opaque = 0;
    p.margin = 0;
    p.blended = false;
    // shapes.cpp's rules, per sprite.
    if (s.blend == Blend::opaque || s.blend == Blend::multiply) p.boundary = 2;
    else if (s.color[3] <= 0.0f || !pic.has_boundary) p.boundary = 0;
    else p.boundary = pic.boundary_inside ? 1 : 2;
    if (p.boundary == 0) return FrameStatus::ok;
    // Frames are for a plain renderer (texel skirts, no coverage skirts):
    // a sprite GL snaps whose picture's edges bleed draws its whole rect,
    // as reconstruction's rect_edges does for such an element.
    if (p.boundary == 1 && needs_rect_edges(pic.bleeding_edges, s.transform)) p.boundary = 2;
    if (options_.opaque_pass) {
        if (s.blend == Blend::opaque) p.opaque = 2;
        else if (s.blend == Blend::alpha && s.color[3] == 1.0f && pic.has_opaque) p.opaque = 1;
    }
    p.blended = !(options_.opaque_pass && s.blend == Blend::opaque);
    // MeshBuilder::element_texel_margin: below a scale of 1/8 the margin
    // grows to 1/256 pixel along the most shrunk direction, at most half a
    // texel. The templates' margin is the next power of two up: a wider
    // skirt still lies outside every polygon (its templates keep 3 margins
    // clear as MeshBuilder does), and the opaque polygons, pulled in
    // further, leave a strip the blend draw then covers, so the sprite
    // blends even where its opaque polygons cover all it shows.
    const auto& t = s.transform;
    const double sum = t[0] * t[0] + t[1] * t[1] + t[2] * t[2] + t[3] * t[3], det = t[0] * t[3] - t[1] * t[2];
    if (64 * det * det < sum) { // else the smallest singular value, >= |det| / sqrt(sum), is >= 1/8
        const double smallest = std::sqrt(std::max(0.0, (sum - std::sqrt(std::max(0.0, sum * sum - 4 * det * det))) / 2));
        if (smallest > 0) {
            const double margin = std::min(0.5, (1.0 / 256) / smallest);
            while (p.margin + 1 < kMarginBuckets && kTexelMargin * double(1 << p.margin) < margin) ++p.margin;
        }
    }
    if (p.opaque == 1 && options_.filter == Filter::nearest && pic.opaque_covers_all && p.boundary == 1 && p.margin == 0)
        p.blended = false;
    return FrameStatus::ok;
}

std::uint32_t FrameAssembler::emit(const Template& t, const Sprite& s, float z, bool stream, AssembledFrame* out) {
    const auto base = std::uint32_t(out->vertices.size() / kVertexFloats);
    const std::size_t n = t.xy.size() / 2;
    const std::size_t first = out->vertices.size();
    out->vertices.resize(first + n * kVertexFloats);
    // Locals: the stores through v (floats) could otherwise alias the
    // sprite's colour, reloaded for every vertex.
    const double a = s.transform[0], b = s.transform[1], c = s.transform[2], d = s.transform[3], e = s.transform[4],
                 f = s.transform[5];
    const float r = s.color[0], g = s.color[1], bl = s.color[2], al = s.color[3];
    const double* xy = t.xy.data();
    const float* uv = t.uv.data();
    float* v = out->vertices.data() + first;
    std::size_t k = 0;
#if !DEPTHCULL_STREAM_VERTICES
    (void)stream;
#else
    // Streaming stores for frames too big for the caches: their vertices
    // are written once and read by the upload, so they bypass the cache
    // rather than read each line in first (half the memory traffic; a frame
    // of 100,000 sprites writes 40 MB). Templates hold whole groups of 4
    // vertices (to_template pads them), so every group starts 16-byte
    // aligned and fills whole lines in order.
    if (stream && n % 4 == 0 && reinterpret_cast<std::uintptr_t>(v) % 16 == 0)
        for (; k < n; k += 4, v += 4 * kVertexFloats) {
            float px[4], py[4];
            for (std::size_t j = 0; j < 4; ++j) {
                const double x = xy[2 * (k + j)], y = xy[2 * (k + j) + 1];
                px[j] = float(a * x + c * y + e), py[j] = float(b * x + d * y + f);
            }
            const float* w = uv + 2 * k;
            _mm_stream_ps(v + 0, _mm_setr_ps(px[0], py[0], z, w[0]));
            _mm_stream_ps(v + 4, _mm_setr_ps(w[1], r, g, bl));
            _mm_stream_ps(v + 8, _mm_setr_ps(al, px[1], py[1], z));
            _mm_stream_ps(v + 12, _mm_setr_ps(w[2], w[3], r, g));
            _mm_stream_ps(v + 16, _mm_setr_ps(bl, al, px[2], py[2]));
            _mm_stream_ps(v + 20, _mm_setr_ps(z, w[4], w[5], r));
            _mm_stream_ps(v + 24, _mm_setr_ps(g, bl, al, px[3]));
            _mm_stream_ps(v + 28, _mm_setr_ps(py[3], z, w[6], w[7]));
            _mm_stream_ps(v + 32, _mm_setr_ps(r, g, bl, al));
        }
#endif
    for (; k < n; ++k, v += kVertexFloats) {
        const double x = xy[2 * k], y = xy[2 * k + 1];
        // apply(): the same operations, so the same roundings.
        v[0] = float(a * x + c * y + e), v[1] = float(b * x + d * y + f), v[2] = z, v[3] = uv[2 * k], v[4] = uv[2 * k + 1];
        v[5] = r, v[6] = g, v[7] = bl, v[8] = al;
    }
    return base;
}

// One pass over the sprites in painter's order plans each, writes its
// vertices (sprites and vertices read and written in sequence) and finds
// its blend batch; the draws then only place indices, each sprite's at its
// draw's cursor (a counting sort by draw), in two more passes.
FrameStatus FrameAssembler::run(const Viewport& bounds, AssembledFrame* out) {
    const std::size_t n = ranges_.empty() ? 0 : ranges_.back().end;
    plan_.resize(n);
    // The last frame's size tells whether this one outgrows the caches
    // (the stores differ, the vertices written do not).
    const bool stream = out->vertices.size() * sizeof(float) > kStreamBytes;
    out->vertices.clear();
    out->indices.clear();
    out->draws.clear();
    out->points.clear();
    out->stats = {};
    out->stats.sprites = std::int64_t(n);
    out->depth_test = options_.opaque_pass;
    out->depth_denominator = denominator_;
    const std::size_t keys = std::size_t(max_texture_ + 1) * 4;
    key_count_.assign(keys, 0);    // opaque indices per key
    key_nearest_.assign(keys, -1); // per key its nearest opaque sprite
    batch_key_.clear();
    batch_count_.clear(); // blend indices per batch
    point_batch_.clear();
    std::size_t opaque_indices = 0, blend_indices = 0;

    // The overlap grid over `bounds`.
    double cell = options_.cell_size > 0 && std::isfinite(options_.cell_size) ? options_.cell_size : 64;
    const double w = std::max(bounds.width, 1), h = std::max(bounds.height, 1);
    const double max_cells = std::max(options_.max_cells, 1);
    while (std::ceil(w / cell) * std::ceil(h / cell) > max_cells) cell *= 2;
    const int cols = int(std::ceil(w / cell)), rows = int(std::ceil(h / cell));
    const double inv = 1 / cell;
    // int(c) is floor(c) for c >= 0, and c < 0 clamps to 0 anyway.
    auto clamp_cell = [](double c, int n) { return c < 0 ? 0 : c >= n ? n - 1 : int(c); };

    // depth_z with the reciprocal: within a double rounding of its
    // quotient, so at most a float ulp (2^-24 below 1) off, while levels lie
    // 1/D >= 2^-23 apart: the order of every z, static ones included, holds.
    const double inverse = 1 / double(denominator_);
    auto z_of = [&](std::int64_t level, bool opaque) { return float(double(2 * level + (opaque ? 2 : 1)) * inverse); };
    for (const Range& range : ranges_) {
        // Each point batches on its own (its draws go between other static draws).
        point_batch_.push_back(std::uint32_t(batch_key_.size()));
        cell_top_.assign(std::size_t(cols) * std::size_t(rows), -1);
        last_batch_of_key_.assign(keys, -1);
        std::int32_t all_top = -1, wide_top = -1;
        for (std::size_t i = range.first; i < range.end; ++i) {
            const Sprite& s = range.sprites[i - range.first];
            const std::int64_t level = range.first_level + std::int64_t(i - range.first);
            Plan& p = plan_[i];
            if (FrameStatus st = plan_sprite(s, p); st != FrameStatus::ok) {
#if DEPTHCULL_STREAM_VERTICES
                _mm_sfence();
#endif
                out->vertices.clear();
                out->stats = {};
                return st;
            }
            const Picture& pic = images_[std::size_t(p.picture)];
            if (p.opaque) {
                p.opaque_template = p.opaque == 2 ? &pic.quad : &pic.opaque[p.margin];
                p.opaque_base = emit(*p.opaque_template, s, z_of(level, true), stream, out);
                key_count_[std::size_t(p.key)] += std::int32_t(p.opaque_template->indices.size());
                key_nearest_[std::size_t(p.key)] = std::int64_t(i); // levels grow with i
                opaque_indices += p.opaque_template->indices.size();
            }
            if (!p.blended) continue;
            p.blend_template = p.boundary == 2                                                   ? &pic.quad
                               : s.blend != Blend::opaque && !snaps_exactly(s.transform) ? &pic.boundary[p.margin]
                                                                                             : &pic.plain;
            p.blend_base = emit(*p.blend_template, s, z_of(level, false), stream, out);
            // The screen box of what it draws: its centre's image plus the
            // half extents' absolute images, and a pixel for GL's snapping
            // (and rounding): cells are conservative.
            double x0 = pic.bx0, y0 = pic.by0, x1 = pic.bx1, y1 = pic.by1;
            if (p.boundary == 2) x0 = 0, y0 = 0, x1 = pic.rect.w, y1 = pic.rect.h;
            const auto& m = s.transform;
            const double hx = (x1 - x0) / 2, hy = (y1 - y0) / 2;
            const Vec2 centre = apply(m, {x0 + hx, y0 + hy});
            const double ex = std::abs(m[0]) * hx + std::abs(m[2]) * hy + 1, ey = std::abs(m[1]) * hx + std::abs(m[3]) * hy + 1;
            const int cx0 = clamp_cell((centre.x - ex - bounds.x) * inv, cols);
            const int cx1 = clamp_cell((centre.x + ex - bounds.x) * inv, cols);
            const int cy0 = clamp_cell((centre.y - ey - bounds.y) * inv, rows);
            const int cy1 = clamp_cell((centre.y + ey - bounds.y) * inv, rows);
            const bool wide = std::int64_t(cx1 - cx0 + 1) * (cy1 - cy0 + 1) > options_.cell_budget;
            std::int32_t top = all_top;
            if (!wide) {
                top = wide_top;
                for (int cy = cy0; cy <= cy1; ++cy) {
                    const std::int32_t* row = cell_top_.data() + std::size_t(cy) * std::size_t(cols);
                    for (int cx = cx0; cx <= cx1; ++cx) top = std::max(top, row[cx]);
                }
            } else {
                ++out->stats.over_budget;
            }
            // The earliest batch this sprite may join: after every batch of
            // a sprite it may overlap, or that very batch when it is its own
            // key (a batch draws its sprites in painter's order).
            const std::int32_t lowest = top < 0 ? 0 : batch_key_[std::size_t(top)] == p.key ? top : top + 1;
            std::int32_t b = last_batch_of_key_[std::size_t(p.key)];
            if (b < lowest) {
                b = std::int32_t(batch_key_.size());
                batch_key_.push_back(p.key);
                batch_count_.push_back(0);
                last_batch_of_key_[std::size_t(p.key)] = b;
            }
            p.batch = b;
            batch_count_[std::size_t(b)] += std::int32_t(p.blend_template->indices.size());
            blend_indices += p.blend_template->indices.size();
            all_top = std::max(all_top, b);
            if (wide) wide_top = std::max(wide_top, b);
            else
                for (int cy = cy0; cy <= cy1; ++cy) {
                    std::int32_t* row = cell_top_.data() + std::size_t(cy) * std::size_t(cols);
                    for (int cx = cx0; cx <= cx1; ++cx) row[cx] = std::max(row[cx], b);
                }
        }
    }
    point_batch_.push_back(std::uint32_t(batch_key_.size()));
#if DEPTHCULL_STREAM_VERTICES
    _mm_sfence(); // streaming stores are ordered before whatever reads the frame
#endif
    if (opaque_indices + blend_indices > std::size_t(INT32_MAX)) { // draws count indices in 32 bits
        out->vertices.clear();
        out->stats = {};
        return FrameStatus::too_many_sprites;
    }
    out->indices.resize(opaque_indices + blend_indices);
    std::uint32_t* indices = out->indices.data();
    auto place = [&](const Template& t, std::uint32_t base, std::int32_t& cursor) {
        const std::uint32_t* tx = t.indices.data();
        std::uint32_t* ix = indices + cursor;
        for (std::size_t k = 0, count = t.indices.size(); k < count; ++k) ix[k] = base + tx[k];
        cursor += std::int32_t(t.indices.size());
    };

    // The opaque pass, front to back: keys by their nearest sprite,
    // sprites nearest first (append_opaque_draws' order). Levels grow with
    // the flat index. key_count_ becomes the end of each key's indices,
    // filled backwards as the sprites go forwards.
    if (opaque_indices) {
        key_order_.clear();
        for (std::size_t k = 0; k < keys; ++k)
            if (key_nearest_[k] >= 0) key_order_.push_back(std::int32_t(k));
        std::sort(key_order_.begin(), key_order_.end(),
                  [&](std::int32_t x, std::int32_t y) { return key_nearest_[std::size_t(x)] > key_nearest_[std::size_t(y)]; });
        std::int32_t at = 0;
        for (std::int32_t k : key_order_) {
            const std::int32_t count = key_count_[std::size_t(k)];
            out->draws.push_back({k / 4, Pass::opaque, Blend(k % 4), std::uint32_t(at), std::uint32_t(count)});
            at += count;
            key_count_[std::size_t(k)] = at;
        }
    }
    out->opaque_draws = out->draws.size();

    // The blend pass: each point's batches in order, sprites in painter's
    // order within one. batch_count_ becomes each batch's cursor.
    std::int32_t at = std::int32_t(opaque_indices);
    for (std::size_t r = 0; r < ranges_.size(); ++r) {
        FramePoint point;
        point.static_draw = ranges_[r].static_draw;
        point.first_draw = std::uint32_t(out->draws.size());
        for (std::uint32_t b = point_batch_[r]; b < point_batch_[r + 1]; ++b) {
            const std::int32_t key = batch_key_[b], count = batch_count_[b];
            out->draws.push_back({key / 4, Pass::blend, Blend(key % 4), std::uint32_t(at), std::uint32_t(count)});
            batch_count_[b] = at;
            at += count;
        }
        point.end_draw = std::uint32_t(out->draws.size());
        out->points.push_back(point);
    }
    // One pass places both: blend indices forwards from each batch's
    // cursor, opaque ones backwards from each key's end.
    for (std::size_t i = 0; i < n; ++i) {
        const Plan& p = plan_[i];
        if (p.opaque) {
            std::int32_t& end = key_count_[std::size_t(p.key)];
            end -= std::int32_t(p.opaque_template->indices.size());
            std::int32_t cursor = end;
            place(*p.opaque_template, p.opaque_base, cursor);
        }
        if (p.blended) place(*p.blend_template, p.blend_base, batch_count_[std::size_t(p.batch)]);
    }
    out->stats.draw_calls = std::int64_t(out->draws.size());
    out->stats.opaque_draws = std::int64_t(out->opaque_draws);
    out->stats.blend_batches = out->stats.draw_calls - out->stats.opaque_draws;
    out->stats.triangles = std::int64_t(out->indices.size() / 3);
    return FrameStatus::ok;
}

FrameStatus FrameAssembler::assemble(std::span<const Sprite> sprites, const Viewport& bounds, AssembledFrame* out) {
    if (!out) return FrameStatus::bad_sprite;
    if (std::int64_t(sprites.size()) > kMaxDepthLevels) return FrameStatus::too_many_sprites;
    denominator_ = depth_denominator(std::int64_t(sprites.size()));
    ranges_.clear();
    ranges_.push_back({0, 0, std::uint32_t(sprites.size()), sprites.data(), 0});
    return run(bounds, out);
}

FrameStatus FrameAssembler::assemble_at(const SceneMeshes& static_meshes, std::span<const std::span<const Sprite>> sprites,
                                        const Viewport& bounds, AssembledFrame* out) {
    if (!out || sprites.size() > static_meshes.insertion_points.size() || static_meshes.depth_denominator < 2)
        return FrameStatus::bad_meshes;
    ranges_.clear();
    std::uint32_t at = 0;
    for (std::size_t k = 0; k < sprites.size(); ++k) {
        const InsertionPoint& point = static_meshes.insertion_points[k];
        if (std::int64_t(sprites[k].size()) > point.levels) return FrameStatus::too_many_sprites;
        ranges_.push_back({point.blend_draw, at, at + std::uint32_t(sprites[k].size()), sprites[k].data(), point.first_level});
        at += std::uint32_t(sprites[k].size());
    }
    denominator_ = static_meshes.depth_denominator;
    const FrameStatus st = run(bounds, out);
    out->depth_test = static_meshes.depth_test;
    return st;
}

} // namespace depthcull
