// Paper 2.3: the element graph, an edge from element i to element j < i
// when i, as drawn, overlaps j. The paper's ElementGraph compares all
// pairs; we find candidate pairs with a uniform grid over the screen boxes
// (broad phase) and test the transformed boundary polygons (narrow phase),
// so building it is near-linear when elements are small next to the scene.
// Hostile scenes cannot make it quadratic: see "The bound" below and
// docs/element-graph.md.
//
// The test is conservative about rasterization: a missing edge could let a
// reordered element draw over one it should be behind (the look changes),
// an extra edge only costs batching. So polygons that touch, or come
// closer than kSeparation plus float rounding, count as overlapping:
// vertices reach the GPU as floats (relative error 2^-24) and rasterizers
// snap them to a sub-pixel grid (1/256 pixel on common hardware), so two
// polygons separated by less than that on paper may share a pixel centre.
// Float rounding grows with the coordinates, so the tolerance of a pair is
// taken from the two elements' own coordinates, never the scene's largest:
// one element 3e9 px wide must not make 100,000 small sprites near the
// origin pair up.
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "scene/internal.h"

namespace depthcull::detail {

namespace {

constexpr double kSeparation = 1.0 / 64; // pixels; 4x the worst sub-pixel snap

struct ScreenPolygon {
    std::uint32_t first = 0, count = 0; // into ScreenGeometry::vertices
    Box box;
    bool convex = false;
};

// All elements' polygons transformed to the screen, flat so 100k elements
// cost a handful of allocations.
struct ScreenGeometry {
    std::vector<Vec2> vertices;
    std::vector<ScreenPolygon> polygons;
    std::vector<std::uint32_t> element_first; // polygons of element i: [first[i], first[i+1])
    std::vector<Box> element_box;
    std::vector<double> element_eps; // the element's overlap tolerance (element_tolerance)
    std::vector<std::uint8_t> draws;
};

// kSeparation plus the float rounding of the element's largest screen
// coordinate (2^-22: a float's 2^-24 twice over, for both polygons, with
// room to spare). A pair uses the larger of its two elements'.
double element_tolerance(const Box& b) {
    double m = std::max({std::fabs(b.x0), std::fabs(b.y0), std::fabs(b.x1), std::fabs(b.y1)});
    return kSeparation + m * 0x1p-22;
}

// Convex in either orientation (a mirroring transform flips it), collinear
// vertices allowed. Exact for texel-grid vertices.
bool is_convex_any_orientation(const Polygon& p) {
    bool pos = false, neg = false;
    const std::size_t n = p.size();
    for (std::size_t i = 0; i < n; ++i) {
        double o = orient(p[i], p[(i + 1) % n], p[(i + 2) % n]);
        pos |= o > 0;
        neg |= o < 0;
    }
    return !(pos && neg);
}

void add_polygon(ScreenGeometry& g, const Element& e, const Polygon& p, bool convex) {
    ScreenPolygon sp;
    sp.first = std::uint32_t(g.vertices.size());
    sp.count = std::uint32_t(p.size());
    sp.convex = convex;
    sp.box = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    for (const Vec2& v : p) {
        Vec2 s = apply(e.transform, {v.x - e.rect.x, v.y - e.rect.y});
        g.vertices.push_back(s);
        sp.box = {std::min(sp.box.x0, s.x), std::min(sp.box.y0, s.y), std::max(sp.box.x1, s.x), std::max(sp.box.y1, s.y)};
    }
    g.polygons.push_back(sp);
}

ScreenGeometry screen_geometry(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                               const std::vector<Shape>& shapes, GraphMode mode) {
    const std::size_t n = scene.elements.size();
    ScreenGeometry g;
    g.element_first.reserve(n + 1);
    g.element_box.resize(n);
    g.element_eps.resize(n, kSeparation);
    g.draws.resize(n, 0);
    g.vertices.reserve(n * 8);
    g.polygons.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        g.element_first.push_back(std::uint32_t(g.polygons.size()));
        const Element& e = scene.elements[i];
        Shape shape = shapes[i];
        if (shape == Shape::none) continue;
        if (mode == GraphMode::boxes) shape = Shape::rect;
        if (shape == Shape::rect) {
            add_polygon(g, e, rect_polygon(e.rect), true);
        } else {
            for (const Polygon& p : analyses[i]->boundary)
                if (p.size() >= 3) add_polygon(g, e, p, is_convex_any_orientation(p));
        }
        Box b{INFINITY, INFINITY, -INFINITY, -INFINITY};
        for (std::size_t k = g.element_first.back(); k < g.polygons.size(); ++k) {
            const Box& pb = g.polygons[k].box;
            b = {std::min(b.x0, pb.x0), std::min(b.y0, pb.y0), std::max(b.x1, pb.x1), std::max(b.y1, pb.y1)};
        }
        g.element_box[i] = b;
        g.draws[i] = g.polygons.size() > g.element_first.back();
        if (g.draws[i]) g.element_eps[i] = element_tolerance(b);
    }
    g.element_first.push_back(std::uint32_t(g.polygons.size()));
    return g;
}

bool boxes_near(const Box& a, const Box& b, double eps) {
    return a.x0 <= b.x1 + eps && b.x0 <= a.x1 + eps && a.y0 <= b.y1 + eps && b.y0 <= a.y1 + eps;
}

// Separating axis test along the edge normals of `a`: true when some edge
// of `a` has all of `b` more than eps beyond it (valid for non-convex
// polygons too: disjoint projections prove disjoint shapes).
bool separated_by_edges_of(const Vec2* a, std::uint32_t na, const Vec2* b, std::uint32_t nb, double eps) {
    for (std::uint32_t i = 0; i < na; ++i) {
        Vec2 p = a[i], q = a[(i + 1) % na];
        Vec2 n{q.y - p.y, p.x - q.x};
        double len = std::sqrt(n.x * n.x + n.y * n.y);
        if (len == 0) continue;
        double amin = INFINITY, amax = -INFINITY, bmin = INFINITY, bmax = -INFINITY;
        for (std::uint32_t k = 0; k < na; ++k) {
            double d = n.x * a[k].x + n.y * a[k].y;
            amin = std::min(amin, d);
            amax = std::max(amax, d);
        }
        for (std::uint32_t k = 0; k < nb; ++k) {
            double d = n.x * b[k].x + n.y * b[k].y;
            bmin = std::min(bmin, d);
            bmax = std::max(bmax, d);
        }
        if (bmin > amax + eps * len || amin > bmax + eps * len) return true;
    }
    return false;
}

double point_segment_distance2(Vec2 p, Vec2 a, Vec2 b) {
    Vec2 ab = b - a, ap = p - a;
    double len2 = ab.x * ab.x + ab.y * ab.y;
    double t = len2 > 0 ? std::clamp((ap.x * ab.x + ap.y * ab.y) / len2, 0.0, 1.0) : 0.0;
    Vec2 d = ap - t * ab;
    return d.x * d.x + d.y * d.y;
}

bool segments_near(Vec2 p1, Vec2 p2, Vec2 q1, Vec2 q2, double eps) {
    if (std::min(p1.x, p2.x) > std::max(q1.x, q2.x) + eps || std::min(q1.x, q2.x) > std::max(p1.x, p2.x) + eps ||
        std::min(p1.y, p2.y) > std::max(q1.y, q2.y) + eps || std::min(q1.y, q2.y) > std::max(p1.y, p2.y) + eps)
        return false;
    double d1 = orient(q1, q2, p1), d2 = orient(q1, q2, p2), d3 = orient(p1, p2, q1), d4 = orient(p1, p2, q2);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
    double e2 = eps * eps;
    return point_segment_distance2(p1, q1, q2) <= e2 || point_segment_distance2(p2, q1, q2) <= e2 ||
           point_segment_distance2(q1, p1, p2) <= e2 || point_segment_distance2(q2, p1, p2) <= e2;
}

// Even-odd crossing test; only used once no edges are near, so the point
// is well away from the boundary and rounding cannot flip the answer.
bool point_in_polygon(Vec2 p, const Vec2* v, std::uint32_t n) {
    bool inside = false;
    for (std::uint32_t i = 0, j = n - 1; i < n; j = i++) {
        if ((v[i].y > p.y) != (v[j].y > p.y)) {
            double x = v[j].x + (p.y - v[j].y) * (v[i].x - v[j].x) / (v[i].y - v[j].y);
            if (p.x < x) inside = !inside;
        }
    }
    return inside;
}

bool polygons_overlap(const ScreenGeometry& g, const ScreenPolygon& a, const ScreenPolygon& b, double eps) {
    if (!boxes_near(a.box, b.box, eps)) return false;
    const Vec2* va = g.vertices.data() + a.first;
    const Vec2* vb = g.vertices.data() + b.first;
    if (separated_by_edges_of(va, a.count, vb, b.count, eps) || separated_by_edges_of(vb, b.count, va, a.count, eps)) return false;
    if (a.convex && b.convex) return true; // no separating axis between convex shapes: they meet
    for (std::uint32_t i = 0; i < a.count; ++i)
        for (std::uint32_t k = 0; k < b.count; ++k)
            if (segments_near(va[i], va[(i + 1) % a.count], vb[k], vb[(k + 1) % b.count], eps)) return true;
    return point_in_polygon(va[0], vb, b.count) || point_in_polygon(vb[0], va, a.count);
}

bool elements_overlap(const ScreenGeometry& g, std::size_t i, std::size_t j, double eps) {
    for (std::uint32_t p = g.element_first[i]; p < g.element_first[i + 1]; ++p)
        for (std::uint32_t q = g.element_first[j]; q < g.element_first[j + 1]; ++q)
            if (polygons_overlap(g, g.polygons[p], g.polygons[q], eps)) return true;
    return false;
}

// ---- The bound
//
// The broad phase compares at most pair_budget candidate pairs (boxes of
// two elements that share a grid cell, or a large element and any other):
// 50,000 sprites stacked at one spot would otherwise compare 1.25e9 pairs
// and keep as many edges. Where the cells' pairs would exceed the budget,
// the fullest cells become "dense": their pairs are not compared; instead
// every element of a dense cell joins one chain in painter's order, an edge
// from each to the previous chained element and to the previous chained
// element the blend-pass sort sees (the sort ignores the others' edges).
// Two elements sharing a dense cell are then joined by a path from the
// later to the earlier, so the sort keeps their painter's order and the
// later gets the higher depth level, as an edge between them would do:
// always correct, only less reordering. Edges <= pair_budget + 2n.
//
// Elements spanning more than kLargeCells cells (a background; a hostile
// sprite 3e9 px wide) stay out of the grid and are compared with every
// drawn element, at most pair_budget / 2 comparisons in all. Cells are
// about the median element's size (not the mean, which one huge element
// would dominate) and coarsen (x2) until there are at most 4n + 64 cells
// over the small elements' bounds, at most 16n + 1024 cell entries and few
// enough large elements; if no size fits (absurd coordinates), one cell.

constexpr double kLargeCells = 64;

// Cells of side `cell` that [lo, hi] spans, at most, wherever the grid's
// origin lies; infinite for absurd or NaN extents.
double span_cells(double lo, double hi, double cell) {
    double s = std::floor((hi - lo) / cell) + 2;
    return std::isfinite(s) ? s : INFINITY;
}

Box grown(const Box& b, double eps) { return {b.x0 - eps, b.y0 - eps, b.x1 + eps, b.y1 + eps}; }

Box united(const Box& a, const Box& b) {
    return {std::min(a.x0, b.x0), std::min(a.y0, b.y0), std::max(a.x1, b.x1), std::max(a.y1, b.y1)};
}

// A uniform grid over the small drawn elements' boxes (each grown by its
// tolerance), stored as one array of element indices per cell (counting
// sort), ascending within a cell.
struct Grid {
    double x0 = 0, y0 = 0, cell = INFINITY;
    std::int64_t nx = 1, ny = 1;
    std::vector<std::uint32_t> start; // nx*ny + 1
    std::vector<std::uint32_t> items;
    std::vector<std::uint8_t> dense; // per cell: chained, its pairs not compared
    std::vector<std::uint8_t> large; // per element: drawn but not in the grid

    void cell_range(const Box& b, std::int64_t& cx0, std::int64_t& cy0, std::int64_t& cx1, std::int64_t& cy1) const {
        auto clampx = [&](double v, std::int64_t hi) {
            if (!(v >= 0)) return std::int64_t(0); // also NaN
            if (v >= double(hi)) return hi - 1;
            return std::int64_t(v);
        };
        cx0 = clampx((b.x0 - x0) / cell, nx);
        cx1 = clampx((b.x1 - x0) / cell, nx);
        cy0 = clampx((b.y0 - y0) / cell, ny);
        cy1 = clampx((b.y1 - y0) / cell, ny);
    }
};

Grid build_grid(const ScreenGeometry& g, std::uint64_t pair_budget) {
    Grid grid;
    const std::size_t n = g.draws.size();
    grid.large.assign(n, 0);
    std::vector<double> sides;
    for (std::size_t i = 0; i < n; ++i)
        if (g.draws[i]) sides.push_back(std::max(g.element_box[i].x1 - g.element_box[i].x0, g.element_box[i].y1 - g.element_box[i].y0));
    const double drawn = double(sides.size());
    bool fits = false;
    Box all{INFINITY, INFINITY, -INFINITY, -INFINITY};
    if (!sides.empty()) {
        std::nth_element(sides.begin(), sides.begin() + std::ptrdiff_t(sides.size() / 2), sides.end());
        double cell = sides[sides.size() / 2];
        if (!(cell >= 1e-3)) cell = 1e-3; // also NaN
        const double max_cells = 4 * drawn + 64, max_items = 16 * drawn + 1024;
        const double max_large_pairs = double(pair_budget) / 2;
        for (int attempt = 0; attempt < 160; ++attempt, cell *= 2) {
            all = {INFINITY, INFINITY, -INFINITY, -INFINITY};
            double items = 0, large = 0;
            for (std::size_t i = 0; i < n; ++i) {
                if (!g.draws[i]) continue;
                Box b = grown(g.element_box[i], g.element_eps[i]);
                double cells = span_cells(b.x0, b.x1, cell) * span_cells(b.y0, b.y1, cell);
                grid.large[i] = !(cells <= kLargeCells);
                if (grid.large[i]) {
                    ++large;
                } else {
                    items += cells;
                    all = united(all, b);
                }
            }
            double cells = large < drawn ? span_cells(all.x0, all.x1, cell) * span_cells(all.y0, all.y1, cell) : 1;
            if (cells <= max_cells && items <= max_items && large * drawn <= max_large_pairs) {
                fits = true;
                grid.cell = cell;
                break;
            }
        }
    }
    if (fits && all.x0 <= all.x1) {
        grid.x0 = all.x0;
        grid.y0 = all.y0;
        grid.nx = std::max<std::int64_t>(1, std::int64_t(std::ceil((all.x1 - all.x0) / grid.cell)));
        grid.ny = std::max<std::int64_t>(1, std::int64_t(std::ceil((all.y1 - all.y0) / grid.cell)));
    } else if (!fits) {
        std::fill(grid.large.begin(), grid.large.end(), 0); // one cell, everything in it
    }
    grid.start.assign(std::size_t(grid.nx * grid.ny + 1), 0);
    auto for_cells = [&](std::size_t i, auto&& fn) {
        std::int64_t cx0, cy0, cx1, cy1;
        grid.cell_range(grown(g.element_box[i], g.element_eps[i]), cx0, cy0, cx1, cy1);
        for (std::int64_t cy = cy0; cy <= cy1; ++cy)
            for (std::int64_t cx = cx0; cx <= cx1; ++cx) fn(std::size_t(cy * grid.nx + cx));
    };
    auto in_grid = [&](std::size_t i) { return g.draws[i] && !grid.large[i]; };
    for (std::size_t i = 0; i < n; ++i)
        if (in_grid(i)) for_cells(i, [&](std::size_t c) { ++grid.start[c + 1]; });
    for (std::size_t c = 1; c < grid.start.size(); ++c) grid.start[c] += grid.start[c - 1];
    grid.items.resize(grid.start.back());
    std::vector<std::uint32_t> fill(grid.start.begin(), grid.start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
        if (in_grid(i)) for_cells(i, [&](std::size_t c) { grid.items[fill[c]++] = std::uint32_t(i); });

    // Dense cells: the fullest, until the rest's pairs fit what the large
    // elements' comparisons leave of the budget.
    std::uint64_t large_pairs = 0;
    for (std::size_t i = 0; i < n; ++i) large_pairs += grid.large[i] ? std::uint64_t(drawn) : 0;
    const std::uint64_t budget = pair_budget - std::min(pair_budget, large_pairs);
    const std::size_t cells = grid.start.size() - 1;
    auto pairs_in = [&](std::size_t c) {
        std::uint64_t s = grid.start[c + 1] - grid.start[c];
        return s * (s - (s > 0)) / 2;
    };
    grid.dense.assign(cells, 0);
    std::uint64_t total = 0;
    std::vector<std::uint32_t> filled;
    for (std::size_t c = 0; c < cells; ++c) {
        total += pairs_in(c);
        if (pairs_in(c) > 0) filled.push_back(std::uint32_t(c));
    }
    if (total > budget) {
        std::sort(filled.begin(), filled.end(), [&](std::uint32_t a, std::uint32_t b) {
            std::uint64_t pa = pairs_in(a), pb = pairs_in(b);
            return pa != pb ? pa > pb : a < b;
        });
        for (std::uint32_t c : filled) {
            if (total <= budget) break;
            grid.dense[c] = 1;
            total -= pairs_in(c);
        }
    }
    return grid;
}

// The geometry of the drawn elements in the order of their box centres'
// grid cells, so the narrow phase, which visits neighbours on screen,
// reads neighbouring memory: random painter's order otherwise makes large
// scenes cache-bound. rank[i] is element i's place in the copy.
ScreenGeometry spatial_copy(const ScreenGeometry& g, const Grid& grid, std::vector<std::uint32_t>& rank) {
    const std::size_t n = g.draws.size();
    std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
    keyed.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (!g.draws[i]) continue;
        const Box& b = g.element_box[i];
        Box centre{(b.x0 + b.x1) / 2, (b.y0 + b.y1) / 2, (b.x0 + b.x1) / 2, (b.y0 + b.y1) / 2};
        std::int64_t cx0, cy0, cx1, cy1;
        grid.cell_range(centre, cx0, cy0, cx1, cy1);
        keyed.push_back({std::uint64_t(cy0 * grid.nx + cx0), std::uint32_t(i)});
    }
    std::sort(keyed.begin(), keyed.end());
    ScreenGeometry local;
    local.vertices.reserve(g.vertices.size());
    local.polygons.reserve(g.polygons.size());
    local.element_first.reserve(keyed.size() + 1);
    local.element_box.reserve(keyed.size());
    local.element_eps.reserve(keyed.size());
    rank.assign(n, std::uint32_t(-1));
    for (const auto& [cell, i] : keyed) {
        rank[i] = std::uint32_t(local.element_box.size());
        local.element_first.push_back(std::uint32_t(local.polygons.size()));
        local.element_box.push_back(g.element_box[i]);
        local.element_eps.push_back(g.element_eps[i]);
        for (std::uint32_t p = g.element_first[i]; p < g.element_first[i + 1]; ++p) {
            ScreenPolygon sp = g.polygons[p];
            std::uint32_t first = std::uint32_t(local.vertices.size());
            local.vertices.insert(local.vertices.end(), g.vertices.begin() + sp.first, g.vertices.begin() + sp.first + sp.count);
            sp.first = first;
            local.polygons.push_back(sp);
        }
    }
    local.element_first.push_back(std::uint32_t(local.polygons.size()));
    return local;
}

} // namespace

ElementGraph build_graph(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                         const std::vector<Shape>& shapes, GraphMode mode, const std::vector<std::uint8_t>* sorted,
                         std::uint64_t pair_budget) {
    const std::size_t n = scene.elements.size();
    ScreenGeometry g = screen_geometry(scene, analyses, shapes, mode);
    Grid grid = build_grid(g, pair_budget);
    std::vector<std::uint32_t> rank;
    const ScreenGeometry local = spatial_copy(g, grid, rank);
    const std::size_t drawn = local.element_box.size();
    std::vector<std::uint32_t> spatial_order(drawn);
    for (std::size_t i = 0; i < n; ++i)
        if (rank[i] != std::uint32_t(-1)) spatial_order[rank[i]] = std::uint32_t(i);

    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs; // (front, back)
    auto compare = [&](std::uint32_t i, std::uint32_t j, std::uint32_t ri, std::uint32_t rj) {
        const double eps = std::max(local.element_eps[ri], local.element_eps[rj]);
        // A tolerance that is not finite (coordinates beyond any float)
        // proves nothing: keep the edge.
        if (!(eps < INFINITY) || (boxes_near(local.element_box[ri], local.element_box[rj], eps) && elements_overlap(local, ri, rj, eps)))
            pairs.push_back({std::max(i, j), std::min(i, j)});
    };

    // Grid elements in spatial order; each compares the elements behind it
    // (j < i) that share a cell that is not dense.
    std::vector<std::uint32_t> seen(drawn, std::uint32_t(-1));
    for (std::uint32_t ri = 0; ri < drawn; ++ri) {
        const std::uint32_t i = spatial_order[ri];
        if (grid.large[i]) continue;
        std::int64_t cx0, cy0, cx1, cy1;
        grid.cell_range(grown(local.element_box[ri], local.element_eps[ri]), cx0, cy0, cx1, cy1);
        for (std::int64_t cy = cy0; cy <= cy1; ++cy) {
            for (std::int64_t cx = cx0; cx <= cx1; ++cx) {
                std::size_t c = std::size_t(cy * grid.nx + cx);
                if (grid.dense[c]) continue; // the chain orders this cell
                for (std::uint32_t k = grid.start[c]; k < grid.start[c + 1]; ++k) {
                    std::uint32_t j = grid.items[k];
                    if (j >= i) break; // ascending: the rest are in front of i
                    std::uint32_t rj = rank[j];
                    if (seen[rj] == ri) continue;
                    seen[rj] = ri;
                    compare(i, j, ri, rj);
                }
            }
        }
    }
    // Large elements against every drawn element (each large pair once).
    for (std::uint32_t ri = 0; ri < drawn; ++ri) {
        const std::uint32_t i = spatial_order[ri];
        if (!grid.large[i]) continue;
        for (std::uint32_t rj = 0; rj < drawn; ++rj) {
            const std::uint32_t j = spatial_order[rj];
            if (j != i && !(grid.large[j] && j > i)) compare(i, j, ri, rj);
        }
    }
    // The chain through the dense cells' elements, in painter's order.
    std::vector<std::uint8_t> chained(n, 0);
    for (std::size_t c = 0; c + 1 < grid.start.size(); ++c)
        if (grid.dense[c])
            for (std::uint32_t k = grid.start[c]; k < grid.start[c + 1]; ++k) chained[grid.items[k]] = 1;
    std::int64_t prev = -1, prev_sorted = -1;
    for (std::size_t i = 0; i < n; ++i) {
        if (!chained[i]) continue;
        const bool s = !sorted || (i < sorted->size() && (*sorted)[i]);
        if (prev >= 0) pairs.push_back({std::uint32_t(i), std::uint32_t(prev)});
        if (s && prev_sorted >= 0 && prev_sorted != prev) pairs.push_back({std::uint32_t(i), std::uint32_t(prev_sorted)});
        prev = std::int64_t(i);
        if (s) prev_sorted = std::int64_t(i);
    }

    // Gather into painter's order; a chain edge may repeat an overlap edge.
    ElementGraph graph;
    graph.offsets.assign(n + 1, 0);
    for (const auto& pr : pairs) ++graph.offsets[pr.first + 1];
    for (std::size_t i = 1; i <= n; ++i) graph.offsets[i] += graph.offsets[i - 1];
    graph.targets.resize(pairs.size());
    {
        std::vector<std::uint32_t> fill(graph.offsets.begin(), graph.offsets.end() - 1);
        for (const auto& [front, back] : pairs) graph.targets[fill[front]++] = back;
    }
    pairs = {};
    std::uint32_t out = 0;
    for (std::size_t i = 0; i < n; ++i) {
        auto b = graph.targets.begin() + graph.offsets[i], e = graph.targets.begin() + graph.offsets[i + 1];
        std::sort(b, e);
        e = std::unique(b, e);
        graph.offsets[i] = out;
        out = std::uint32_t(std::copy(b, e, graph.targets.begin() + out) - graph.targets.begin());
    }
    graph.offsets[n] = out;
    graph.targets.resize(out);
    graph.targets.shrink_to_fit();
    if (std::find(chained.begin(), chained.end(), std::uint8_t(1)) != chained.end()) graph.chained = std::move(chained);
    return graph;
}

// Graphs kept for the frames of one scene (ReconstructOptions::graph_memo).
// An entry holds all build_graph reads besides the scene: each element's
// shape, its boundary polygons (each distinct set once, elements naming
// theirs), the mode, the budget, and `sorted` where the graph chains (the
// only place it is read). The least recently used entry gives way. Its
// memory is bounded (kMaxBytes, about what the entries hold): a graph
// that does not fit is built each time, as without a memo.
struct GraphMemo {
    struct Entry {
        std::vector<Shape> shapes;
        std::vector<std::uint32_t> set_of; // per element with Shape::analysis: its polygons in `sets`
        std::vector<std::vector<Polygon>> sets;
        std::vector<std::uint8_t> sorted; // where graph.chained is not empty
        GraphMode mode = GraphMode::polygons;
        std::uint64_t budget = 0;
        ElementGraph graph;
        std::size_t bytes = 0;
        std::uint64_t used = 0;
    };
    static constexpr std::size_t kMaxEntries = 8;
    static constexpr std::size_t kMaxBytes = std::size_t(64) << 20;
    const Scene* scene = nullptr;
    std::size_t elements = 0;
    std::vector<Entry> entries;
    std::size_t bytes = 0; // held by the entries
    std::uint64_t clock = 0;
    std::int64_t reused = 0;
};

namespace {

// `sorted` as build_graph reads it (null: every element).
std::vector<std::uint8_t> sorted_flags(const std::vector<std::uint8_t>* sorted, std::size_t n) {
    std::vector<std::uint8_t> out(n, 1);
    if (sorted)
        for (std::size_t i = 0; i < n; ++i) out[i] = i < sorted->size() && (*sorted)[i] ? 1 : 0;
    return out;
}

bool built_from(const GraphMemo::Entry& e, const std::vector<const ImageAnalysis*>& analyses, const std::vector<Shape>& shapes,
                GraphMode mode, const std::vector<std::uint8_t>* sorted, std::uint64_t budget) {
    if (e.mode != mode || e.budget != budget || e.shapes != shapes) return false;
    // Each analysis is compared with its first element's set; the rest of
    // its elements must then name that set. (An entry keeps a set per
    // analysis it was built from, so two of them holding equal polygons
    // can only make an equal build be made again, never a wrong one.)
    std::unordered_map<const ImageAnalysis*, std::uint32_t> set_of_analysis;
    for (std::size_t i = 0; i < shapes.size(); ++i) {
        if (shapes[i] != Shape::analysis) continue;
        const auto [it, fresh] = set_of_analysis.emplace(analyses[i], e.set_of[i]);
        if (fresh ? !(analyses[i] && analyses[i]->boundary == e.sets[e.set_of[i]]) : it->second != e.set_of[i]) return false;
    }
    return e.graph.chained.empty() || e.sorted == sorted_flags(sorted, shapes.size());
}

} // namespace

ElementGraph build_graph(GraphMemo* memo, const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                         const std::vector<Shape>& shapes, GraphMode mode, const std::vector<std::uint8_t>* sorted,
                         std::uint64_t pair_budget) {
    const std::size_t n = scene.elements.size();
    bool usable = memo && shapes.size() == n && analyses.size() == n;
    for (std::size_t i = 0; usable && i < n; ++i) usable = shapes[i] != Shape::analysis || analyses[i];
    if (!usable) return build_graph(scene, analyses, shapes, mode, sorted, pair_budget);
    if (memo->scene != &scene || memo->elements != n) *memo = GraphMemo{}, memo->scene = &scene, memo->elements = n;
    ++memo->clock;
    for (GraphMemo::Entry& e : memo->entries)
        if (built_from(e, analyses, shapes, mode, sorted, pair_budget)) {
            e.used = memo->clock;
            ++memo->reused;
            return e.graph;
        }

    GraphMemo::Entry e;
    e.graph = build_graph(scene, analyses, shapes, mode, sorted, pair_budget);
    e.shapes = shapes;
    e.mode = mode;
    e.budget = pair_budget;
    e.used = memo->clock;
    e.set_of.assign(n, std::uint32_t(-1));
    std::unordered_map<const ImageAnalysis*, std::uint32_t> index;
    for (std::size_t i = 0; i < n; ++i) {
        if (shapes[i] != Shape::analysis) continue;
        const auto [it, fresh] = index.emplace(analyses[i], std::uint32_t(e.sets.size()));
        if (fresh) e.sets.push_back(analyses[i]->boundary);
        e.set_of[i] = it->second;
    }
    if (!e.graph.chained.empty()) e.sorted = sorted_flags(sorted, n);
    e.bytes = sizeof(GraphMemo::Entry) + n * (sizeof(Shape) + sizeof(std::uint32_t)) + e.sorted.size() +
              (e.graph.offsets.size() + e.graph.targets.size()) * sizeof(std::uint32_t) + e.graph.chained.size();
    for (const std::vector<Polygon>& set : e.sets)
        for (const Polygon& p : set) e.bytes += sizeof(Polygon) + p.size() * sizeof(Vec2);
    if (e.bytes > GraphMemo::kMaxBytes) return std::move(e.graph);
    // Room made by the least recently used entries.
    while (!memo->entries.empty() && (memo->entries.size() >= GraphMemo::kMaxEntries || memo->bytes + e.bytes > GraphMemo::kMaxBytes)) {
        auto oldest = std::min_element(memo->entries.begin(), memo->entries.end(),
                                       [](const GraphMemo::Entry& a, const GraphMemo::Entry& b) { return a.used < b.used; });
        memo->bytes -= oldest->bytes;
        memo->entries.erase(oldest);
    }
    memo->bytes += e.bytes;
    memo->entries.push_back(std::move(e));
    return memo->entries.back().graph;
}

void GraphMemoDelete::operator()(GraphMemo* memo) const { delete memo; }
std::unique_ptr<GraphMemo, GraphMemoDelete> make_graph_memo() { return std::unique_ptr<GraphMemo, GraphMemoDelete>(new GraphMemo); }
std::int64_t graph_memo_reused(const GraphMemo& memo) { return memo.reused; }

} // namespace depthcull::detail

namespace depthcull {

bool ElementGraph::has_edge(std::size_t front, std::size_t back) const {
    if (front >= size()) return false;
    return std::binary_search(behind_begin(front), behind_end(front), std::uint32_t(back));
}

std::vector<std::vector<std::uint32_t>> ElementGraph::in_front() const {
    std::vector<std::vector<std::uint32_t>> out(size());
    for (std::size_t i = 0; i < size(); ++i)
        for (const std::uint32_t* b = behind_begin(i); b != behind_end(i); ++b) out[*b].push_back(std::uint32_t(i));
    return out;
}

ElementGraph build_element_graph(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses, GraphMode mode,
                                 std::uint64_t pair_budget) {
    std::vector<const ImageAnalysis*> a = analyses;
    a.resize(scene.elements.size(), nullptr);
    detail::ElementShapes shapes = detail::element_shapes(scene, a, false);
    return detail::build_graph(scene, a, shapes.boundary, mode, nullptr, pair_budget);
}

ElementGraph build_element_graph(const Scene& scene, const SceneAnalysis& analysis, GraphMode mode, std::uint64_t pair_budget) {
    return build_element_graph(scene, analysis.per_element(), mode, pair_budget);
}

} // namespace depthcull
