// Paper 2.1.3: transparent corner removal.
//
// For five consecutive vertices M, A, B, C, N, a convex vertex B can go
// with one of three triangles: ABC itself; A, B and where line MA meets
// edge BC; B, C and where line NC meets edge AB. The paper traces every
// pixel of the triangle; here each variant is only proposed, and
// accept_candidate decides it exactly (the removed triangle is bounded by
// the edges the two polygons do not share).
//
// The two intersection points are rational; they are rounded to the grid
// point just outside the extended line, so the polygon keeps the far side
// of that line (a sliver at most) rather than cutting into texels.
#include "boundary/boundary_internal.h"

namespace depthcull::boundary {

namespace {

Pt at(const IPolygon& p, int i) {
    int n = int(p.size());
    return p[std::size_t(((i % n) + n) % n)];
}

// Copy of p with vertex i removed and vertex `moved` (i-1 or i+1) set to v.
IPolygon without(const IPolygon& p, int i, int moved, Pt v) {
    int n = int(p.size());
    IPolygon q;
    q.reserve(p.size());
    for (int k = 0; k < n; ++k) {
        if (k == i) continue;
        q.push_back(k == ((moved % n) + n) % n ? v : p[std::size_t(k)]);
    }
    return q;
}

// The point where line (l0, l1) meets segment (s0, s1), rounded outward of
// the polygon edge e0 -> e1 that will run along the line. False when
// parallel or outside the segment.
bool line_meets_edge(Pt l0, Pt l1, Pt s0, Pt s1, Pt e0, Pt e1, Pt& out) {
    std::int64_t den = cross(l1 - l0, s1 - s0);
    if (den == 0) return false;
    std::int64_t num = -cross(l1 - l0, s0 - l0); // s = num / den along s0 -> s1
    if (den < 0) num = -num, den = -den;
    if (num < 0 || num > den) return false;
    out = round_outward(e0, e1, s0, s1 - s0, num, den);
    return true;
}

} // namespace

void remove_transparent_corner(const IPolygon& p, int i, std::vector<Candidate>& out) {
    int n = int(p.size());
    if (n < 4) return;
    Pt m = at(p, i - 2), a = at(p, i - 1), b = at(p, i), c = at(p, i + 1), nn = at(p, i + 2);
    // Errata: the test rejects straight and reflex vertices; only a convex
    // corner can be cut away.
    if (orient(a, b, c) <= 0) return;
    auto add = [&](IPolygon q) {
        std::int64_t area2 = twice_area(q);
        out.push_back({std::move(q), area2});
    };
    add(without(p, i, i - 1, a)); // triangle ABC
    Pt x;
    // M -> X runs along M -> A; X -> N along C -> N.
    if (n > 4 && line_meets_edge(m, a, b, c, m, a, x)) add(without(p, i, i - 1, x));
    if (n > 4 && line_meets_edge(nn, c, a, b, c, nn, x)) add(without(p, i, i + 1, x));
}

} // namespace depthcull::boundary
