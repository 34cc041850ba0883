// The convex hull of the occupied cells, reduced to a vertex budget: the
// baseline bench/bench_boundary.cpp compares paper 2.1's polygons against
// (and a possible starting polygon; tried, see boundary_polygon.cpp).
//
// The reduction removes one edge at a time by extending its two
// neighbouring edges until they meet (the new corner rounded to a grid
// point outside both lines, so only area is added), choosing the least area
// increase; each step passes accept_candidate, so the result is exact like
// every other move. It gives up (empty result) when the budget cannot be
// met inside the bounds, e.g. a round sprite that fills its rect.
#include <algorithm>

#include "boundary/boundary_internal.h"

namespace depthcull::boundary {

IPolygon convex_hull(const CellGrid& g) {
    std::vector<Pt> pts;
    for (int y = 0; y < g.height(); ++y) {
        const Run *b = g.row_begin(y), *e = g.row_end(y);
        if (b == e) continue;
        // Only a row's outermost corners can be on the hull.
        for (Pt p : {Pt{b->x0, y}, Pt{(e - 1)->x1, y}, Pt{b->x0, y + 1}, Pt{(e - 1)->x1, y + 1}}) pts.push_back(p);
    }
    std::sort(pts.begin(), pts.end(), [](Pt a, Pt b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
    pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
    if (pts.size() < 3) return pts;
    // Andrew's monotone chain, keeping strict turns with orient < 0
    // (counter-clockwise with y down); reversed to our clockwise order.
    std::vector<Pt> h(2 * pts.size());
    std::size_t k = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        while (k >= 2 && orient(h[k - 2], h[k - 1], pts[i]) >= 0) --k;
        h[k++] = pts[i];
    }
    for (std::size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
        while (k >= t && orient(h[k - 2], h[k - 1], pts[i - 1]) >= 0) --k;
        h[k++] = pts[i - 1];
    }
    h.resize(k - 1);
    std::reverse(h.begin(), h.end());
    return h;
}

namespace {

// The polygon with edge (i, i+1) replaced by the meeting point of the
// extended neighbouring edges; false when they do not meet ahead.
bool remove_edge(const IPolygon& p, std::size_t i, const Bounds& bounds, IPolygon& out, std::int64_t& delta2) {
    const std::size_t n = p.size();
    const Pt a0 = p[(i + n - 1) % n], a1 = p[i], b0 = p[(i + 1) % n], b1 = p[(i + 2) % n];
    const Pt da = a1 - a0, db = b1 - b0;
    const std::int64_t den = cross(da, db);
    if (den <= 0) return false; // parallel, or the lines meet behind the edge
    const std::int64_t num = cross(b0 - a1, db); // X = a1 + da * num / den
    if (num < 0) return false;
    const std::int64_t fx = floor_div(a1.x * den + da.x * num, den), fy = floor_div(a1.y * den + da.y * num, den);
    bool found = false;
    Pt best{};
    std::int64_t best_delta = 0;
    for (std::int64_t dy = 0; dy <= 1; ++dy)
        for (std::int64_t dx = 0; dx <= 1; ++dx) {
            Pt x{fx + dx, fy + dy};
            if (!bounds.contains(x) || orient(a0, a1, x) > 0 || orient(b0, b1, x) > 0) continue;
            std::int64_t d = cross(a0, x) + cross(x, b1) - cross(a0, a1) - cross(a1, b0) - cross(b0, b1);
            if (!found || d < best_delta) best = x, best_delta = d, found = true;
        }
    if (!found) return false;
    out.clear();
    for (std::size_t k = 0; k < n; ++k)
        if (k == i) out.push_back(best);
        else if (k != (i + 1) % n) out.push_back(p[k]);
    delta2 = best_delta;
    return true;
}

} // namespace

IPolygon reduced_convex_hull(const CellGrid& grid, const Bounds& bounds, int max_vertices) {
    IPolygon p = convex_hull(grid);
    if (p.size() < 3) return {};
    IPolygon q;
    std::vector<std::pair<std::int64_t, std::size_t>> order;
    while (int(p.size()) > max_vertices) {
        order.clear();
        std::int64_t delta2 = 0;
        for (std::size_t i = 0; i < p.size(); ++i)
            if (remove_edge(p, i, bounds, q, delta2)) order.push_back({delta2, i});
        std::sort(order.begin(), order.end());
        bool removed = false;
        for (auto [d, i] : order) {
            remove_edge(p, i, bounds, q, delta2);
            if (accept_candidate(grid, bounds, int(p.size()) - 1, p, q)) {
                p = q;
                removed = true;
                break;
            }
        }
        if (!removed) return {}; // cannot meet the budget inside the bounds
    }
    return p;
}

} // namespace depthcull::boundary
