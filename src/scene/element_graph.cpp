// Paper 2.3: the element graph, an edge from element i to element j < i
// when i, as drawn, overlaps j. The paper's ElementGraph compares all
// pairs; we find candidate pairs with a uniform grid over the screen boxes
// (broad phase) and test the transformed boundary polygons (narrow phase),
// so building it is near-linear when elements are small next to the scene.
//
// The test is conservative about rasterization: a missing edge could let a
// reordered element draw over one it should be behind (the look changes),
// an extra edge only costs batching. So polygons that touch, or come
// closer than kSeparation plus float rounding, count as overlapping:
// vertices reach the GPU as floats (relative error 2^-24) and rasterizers
// snap them to a sub-pixel grid (1/256 pixel on common hardware), so two
// polygons separated by less than that on paper may share a pixel centre.
#include <algorithm>
#include <cmath>

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
    std::vector<std::uint8_t> draws;
    double max_coordinate = 0;
};

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
        g.max_coordinate = std::max({g.max_coordinate, std::fabs(s.x), std::fabs(s.y)});
    }
    g.polygons.push_back(sp);
}

ScreenGeometry screen_geometry(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                               const std::vector<Shape>& shapes, GraphMode mode) {
    const std::size_t n = scene.elements.size();
    ScreenGeometry g;
    g.element_first.reserve(n + 1);
    g.element_box.resize(n);
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

// A uniform grid over the drawn elements' boxes, stored as one array of
// element indices per cell (counting sort), ascending within a cell.
struct Grid {
    double x0 = 0, y0 = 0, cell = 1;
    std::int64_t nx = 1, ny = 1;
    std::vector<std::uint32_t> start; // nx*ny + 1
    std::vector<std::uint32_t> items;

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

Grid build_grid(const ScreenGeometry& g, double eps) {
    Grid grid;
    const std::size_t n = g.draws.size();
    Box all{INFINITY, INFINITY, -INFINITY, -INFINITY};
    double sum_side = 0;
    std::size_t drawn = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!g.draws[i]) continue;
        const Box& b = g.element_box[i];
        all = {std::min(all.x0, b.x0), std::min(all.y0, b.y0), std::max(all.x1, b.x1), std::max(all.y1, b.y1)};
        sum_side += std::max(b.x1 - b.x0, b.y1 - b.y0);
        ++drawn;
    }
    if (drawn == 0) {
        grid.start.assign(2, 0);
        return grid;
    }
    grid.x0 = all.x0 - eps;
    grid.y0 = all.y0 - eps;
    double w = all.x1 - all.x0 + 2 * eps, h = all.y1 - all.y0 + 2 * eps;
    // Cells about the size of an average element, so an element touches a
    // few cells; at most ~4 cells per element so sparse scenes stay small.
    grid.cell = std::max(sum_side / double(drawn), 1e-3);
    const double max_cells = 4.0 * double(drawn) + 64;
    if (!std::isfinite(w) || !std::isfinite(h) || !std::isfinite(grid.cell)) {
        grid.cell = INFINITY; // absurd coordinates: one cell, all pairs
    } else {
        while ((std::ceil(w / grid.cell) * std::ceil(h / grid.cell)) > max_cells) grid.cell *= 1.5;
        grid.nx = std::max<std::int64_t>(1, std::int64_t(std::ceil(w / grid.cell)));
        grid.ny = std::max<std::int64_t>(1, std::int64_t(std::ceil(h / grid.cell)));
    }
    grid.start.assign(std::size_t(grid.nx * grid.ny + 1), 0);
    auto for_cells = [&](std::size_t i, auto&& fn) {
        Box b = g.element_box[i];
        b = {b.x0 - eps, b.y0 - eps, b.x1 + eps, b.y1 + eps};
        std::int64_t cx0, cy0, cx1, cy1;
        grid.cell_range(b, cx0, cy0, cx1, cy1);
        for (std::int64_t cy = cy0; cy <= cy1; ++cy)
            for (std::int64_t cx = cx0; cx <= cx1; ++cx) fn(std::size_t(cy * grid.nx + cx));
    };
    for (std::size_t i = 0; i < n; ++i)
        if (g.draws[i]) for_cells(i, [&](std::size_t c) { ++grid.start[c + 1]; });
    for (std::size_t c = 1; c < grid.start.size(); ++c) grid.start[c] += grid.start[c - 1];
    grid.items.resize(grid.start.back());
    std::vector<std::uint32_t> fill(grid.start.begin(), grid.start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
        if (g.draws[i]) for_cells(i, [&](std::size_t c) { grid.items[fill[c]++] = std::uint32_t(i); });
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
    rank.assign(n, std::uint32_t(-1));
    for (const auto& [cell, i] : keyed) {
        rank[i] = std::uint32_t(local.element_box.size());
        local.element_first.push_back(std::uint32_t(local.polygons.size()));
        local.element_box.push_back(g.element_box[i]);
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
                         const std::vector<Shape>& shapes, GraphMode mode) {
    const std::size_t n = scene.elements.size();
    ScreenGeometry g = screen_geometry(scene, analyses, shapes, mode);
    const double eps = kSeparation + g.max_coordinate * 0x1p-22;
    Grid grid = build_grid(g, eps);
    std::vector<std::uint32_t> rank;
    const ScreenGeometry local = spatial_copy(g, grid, rank);
    std::vector<std::uint32_t> spatial_order(local.element_box.size());
    for (std::size_t i = 0; i < n; ++i)
        if (rank[i] != std::uint32_t(-1)) spatial_order[rank[i]] = std::uint32_t(i);

    // Visit elements in spatial order; each finds the overlapping elements
    // behind it (j < i). Then gather the lists into painter's order.
    std::vector<std::uint32_t> count(n + 1, 0);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs; // (front, back)
    std::vector<std::uint32_t> seen(local.element_box.size(), std::uint32_t(-1));
    for (std::uint32_t ri = 0; ri < spatial_order.size(); ++ri) {
        const std::uint32_t i = spatial_order[ri];
        Box b = local.element_box[ri];
        b = {b.x0 - eps, b.y0 - eps, b.x1 + eps, b.y1 + eps};
        std::int64_t cx0, cy0, cx1, cy1;
        grid.cell_range(b, cx0, cy0, cx1, cy1);
        for (std::int64_t cy = cy0; cy <= cy1; ++cy) {
            for (std::int64_t cx = cx0; cx <= cx1; ++cx) {
                std::size_t c = std::size_t(cy * grid.nx + cx);
                for (std::uint32_t k = grid.start[c]; k < grid.start[c + 1]; ++k) {
                    std::uint32_t j = grid.items[k];
                    if (j >= i) break; // ascending: the rest are in front of i
                    std::uint32_t rj = rank[j];
                    if (seen[rj] == ri) continue;
                    seen[rj] = ri;
                    if (boxes_near(local.element_box[ri], local.element_box[rj], eps) && elements_overlap(local, ri, rj, eps)) {
                        pairs.push_back({i, j});
                        ++count[i + 1];
                    }
                }
            }
        }
    }
    ElementGraph graph;
    graph.offsets.assign(n + 1, 0);
    for (std::size_t i = 1; i <= n; ++i) graph.offsets[i] = graph.offsets[i - 1] + count[i];
    graph.targets.resize(pairs.size());
    std::vector<std::uint32_t> fill(graph.offsets.begin(), graph.offsets.end() - 1);
    for (const auto& [front, back] : pairs) graph.targets[fill[front]++] = back;
    for (std::size_t i = 0; i < n; ++i)
        std::sort(graph.targets.begin() + graph.offsets[i], graph.targets.begin() + graph.offsets[i + 1]);
    return graph;
}

} // namespace depthcull::detail

namespace depthcull {

bool ElementGraph::has_edge(std::size_t front, std::size_t back) const {
    if (front >= size()) return false;
    return std::binary_search(behind_begin(front), behind_end(front), std::uint32_t(back));
}

ElementGraph build_element_graph(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses, GraphMode mode) {
    std::vector<const ImageAnalysis*> a = analyses;
    a.resize(scene.elements.size(), nullptr);
    detail::ElementShapes shapes = detail::element_shapes(scene, a, false);
    return detail::build_graph(scene, a, shapes.boundary, mode);
}

} // namespace depthcull
