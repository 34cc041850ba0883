// Exact containment: the acceptance test every boundary-polygon move must
// pass, and the polygon predicates it uses.
//
// Why it is sound. Let U be the union of the occupied (closed) cells. If no
// edge of a polygon Q meets the interior of U, every connected piece of
// int(U) lies wholly inside or wholly outside Q; a run of cells in one row is
// such a piece, so testing one cell centre per run decides the whole run.
// When Q comes from a polygon P that contained every cell, the cells Q lost
// lie in P \ Q, whose outline is made of the edges P and Q do not share; so
// only runs inside the bounding box of those edges need a centre test.
#include <algorithm>

#include "boundary/boundary_internal.h"
#include "common/segments.h"

namespace depthcull::boundary {

std::int64_t twice_area(const IPolygon& p) {
    std::int64_t sum = 0;
    for (std::size_t i = 0, n = p.size(); i < n; ++i) sum += cross(p[i], p[(i + 1) % n]);
    return sum;
}

void remove_degenerate_vertices(IPolygon& p) {
    bool changed = true;
    while (changed && p.size() >= 3) {
        changed = false;
        for (std::size_t i = 0; i < p.size() && p.size() >= 3; ++i) {
            std::size_t n = p.size();
            Pt prev = p[(i + n - 1) % n], next = p[(i + 1) % n];
            if (p[i] == next || orient(prev, p[i], next) == 0) {
                p.erase(p.begin() + std::ptrdiff_t(i));
                changed = true;
                --i; // re-test the vertex that moved into slot i
            }
        }
    }
}

namespace {

bool on_segment(Pt a, Pt b, Pt p) {
    return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
           p.y <= std::max(a.y, b.y);
}

} // namespace

bool is_simple(const IPolygon& p) {
    std::size_t n = p.size();
    if (n < 3) return false;
    for (std::size_t i = 0; i < n; ++i) {
        Pt a = p[i], b = p[(i + 1) % n];
        if (a == b) return false;
        for (std::size_t j = i + 1; j < n; ++j) {
            Pt c = p[j], d = p[(j + 1) % n];
            bool next = j == i + 1, wrap = i == 0 && j == n - 1;
            if (!next && !wrap) {
                if (segments_touch(a, b, c, d)) return false;
                continue;
            }
            // Adjacent edges share one vertex; they must not fold back
            // along each other.
            Pt shared = next ? b : a, u = (next ? a : b) - shared, v = (next ? d : c) - shared;
            if (cross(u, v) == 0 && u.x * v.x + u.y * v.y > 0) return false;
        }
    }
    return true;
}

bool strictly_inside_doubled(const IPolygon& p, std::int64_t px, std::int64_t py) {
    bool inside = false;
    for (std::size_t i = 0, n = p.size(); i < n; ++i) {
        Pt a{2 * p[i].x, 2 * p[i].y}, b{2 * p[(i + 1) % n].x, 2 * p[(i + 1) % n].y};
        Pt q{px, py};
        std::int64_t o = orient(a, b, q);
        if (o == 0 && on_segment(a, b, q)) return false; // on the boundary
        if ((a.y > py) != (b.y > py)) {
            // q is left of the edge's crossing when orient has the sign
            // that points left for this edge direction.
            bool left = b.y > a.y ? o > 0 : o < 0;
            if (left) inside = !inside;
        }
    }
    return inside;
}

namespace {

bool has_edge(const IPolygon& p, Pt a, Pt b) {
    for (std::size_t i = 0, n = p.size(); i < n; ++i)
        if (p[i] == a && p[(i + 1) % n] == b) return true;
    return false;
}

void grow(Bounds& box, bool& any, Pt a) {
    if (!any) box = {a.x, a.y, a.x, a.y};
    box.x0 = std::min(box.x0, a.x);
    box.y0 = std::min(box.y0, a.y);
    box.x1 = std::max(box.x1, a.x);
    box.y1 = std::max(box.y1, a.y);
    any = true;
}

// Every run of cells overlapping `box` has its first overlapping cell's
// centre strictly inside p.
bool runs_inside(const CellGrid& grid, const IPolygon& p, const Bounds& box) {
    std::int64_t y0 = std::max<std::int64_t>(box.y0 - 1, 0), y1 = std::min<std::int64_t>(box.y1 + 1, grid.height());
    for (std::int64_t y = y0; y < y1; ++y) {
        for (const Run* r = grid.row_begin(int(y)); r != grid.row_end(int(y)); ++r) {
            if (r->x1 <= box.x0 - 1 || r->x0 >= box.x1 + 1) continue;
            std::int64_t x = std::max<std::int64_t>(r->x0, box.x0 - 1);
            if (!strictly_inside_doubled(p, 2 * x + 1, 2 * y + 1)) return false;
        }
    }
    return true;
}

} // namespace

bool accept_candidate(const CellGrid& grid, const Bounds& bounds, int max_vertices, const IPolygon& old,
                      IPolygon& q) {
    remove_degenerate_vertices(q);
    if (q.size() < 3 || int(q.size()) > max_vertices) return false;
    for (Pt v : q)
        if (!bounds.contains(v)) return false;
    if (twice_area(q) <= 0 || !is_simple(q)) return false;
    Bounds changed;
    bool any = false;
    for (std::size_t i = 0, n = q.size(); i < n; ++i) {
        Pt a = q[i], b = q[(i + 1) % n];
        if (has_edge(old, a, b)) continue;
        if (!grid.segment_clear(a, b)) return false;
        grow(changed, any, a);
        grow(changed, any, b);
    }
    for (std::size_t i = 0, n = old.size(); i < n; ++i) {
        Pt a = old[i], b = old[(i + 1) % n];
        if (has_edge(q, a, b)) continue;
        grow(changed, any, a);
        grow(changed, any, b);
    }
    return !any || runs_inside(grid, q, changed);
}

bool contains_all_cells(const CellGrid& grid, const IPolygon& p) {
    if (p.size() < 3) return grid.empty();
    for (std::size_t i = 0, n = p.size(); i < n; ++i)
        if (!grid.segment_clear(p[i], p[(i + 1) % n])) return false;
    return runs_inside(grid, p, {0, 0, grid.width(), grid.height()});
}

} // namespace depthcull::boundary
