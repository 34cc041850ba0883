// Paper 2.1.1: corner cutting.
//
// Two cut points run along the polygon: A from vertex V toward the next
// vertex, B from the previous vertex toward V; for each step of A, B
// advances until segment AB is clear of the texels, and the polygon with
// triangle AVB removed is a candidate.
//
// Departures from the paper, and why:
// - Points along a slanted edge are off the integer grid. They are rounded
//   to the grid point on the outer side of the edge's line, so the polygon
//   only grows there and every predicate stays exact. The result is checked
//   by accept_candidate anyway.
// - Long edges are sampled at most kMaxSteps times, so a 2048-texel sprite
//   costs the same number of IsLineEmpty tests per vertex as a 256-texel one.
#include <algorithm>
#include <cstdlib>

#include "boundary/boundary_internal.h"

namespace depthcull::boundary {

namespace {

constexpr std::int64_t kMaxSteps = 256;

std::int64_t major_length(Pt d) { return std::max(std::llabs(d.x), std::llabs(d.y)); }

} // namespace

Pt round_outward(Pt a, Pt b, Pt base, Pt dir, std::int64_t num, std::int64_t den) {
    std::int64_t fx = floor_div(base.x * den + dir.x * num, den);
    std::int64_t fy = floor_div(base.y * den + dir.y * num, den);
    Pt best{fx, fy};
    bool found = false;
    std::int64_t best_o = 0;
    for (int k = 0; k < 4; ++k) {
        Pt c{fx + (k & 1), fy + (k >> 1)};
        std::int64_t o = orient(a, b, c);
        if (o > 0) continue; // inside the edge: the polygon would cut texels
        if (!found || o > best_o) best = c, best_o = o, found = true;
    }
    return best; // one of the four corners of the cell around the point is never inside
}

void cut_boundary_corner(const CellGrid& grid, const Bounds& bounds, const IPolygon& p, int i,
                         std::vector<Candidate>& out) {
    (void)bounds; // rounding outward may leave the rect; accept_candidate rejects those
    const int n = int(p.size());
    const Pt v = p[std::size_t(i)], prev = p[std::size_t((i + n - 1) % n)], next = p[std::size_t((i + 1) % n)];
    if (orient(prev, v, next) <= 0) return; // cutting a reflex corner would add area

    const Pt da = next - v, db = v - prev;
    const std::int64_t la = major_length(da), lb = major_length(db);
    const std::int64_t step_a = std::max<std::int64_t>(1, (la + kMaxSteps - 1) / kMaxSteps);
    const std::int64_t step_b = std::max<std::int64_t>(1, (lb + kMaxSteps - 1) / kMaxSteps);
    const std::int64_t old_area2 = twice_area(p);

    std::int64_t kb = 0; // B = prev + db * kb / lb
    for (std::int64_t ka = step_a;; ka += step_a) {
        ka = std::min(ka, la);
        Pt a = ka == la ? next : round_outward(v, next, v, da, ka, la);
        Pt b = kb == 0 ? prev : round_outward(prev, v, prev, db, kb, lb);
        while (!grid.segment_clear(a, b)) {
            kb = std::min(kb + step_b, lb);
            if (kb == lb) break;
            b = round_outward(prev, v, prev, db, kb, lb);
        }
        if (kb == lb) break; // B reached V: no cut is possible from here on

        IPolygon q;
        q.reserve(p.size() + 1);
        for (int k = 0; k < n; ++k) {
            if (k == i) {
                q.push_back(b);
                q.push_back(a);
            } else {
                q.push_back(p[std::size_t(k)]);
            }
        }
        std::int64_t area2 = twice_area(q);
        if (area2 < old_area2) out.push_back({std::move(q), area2});
        if (ka == la) break;
    }
}

} // namespace depthcull::boundary
