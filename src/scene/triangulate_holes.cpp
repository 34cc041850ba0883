// Issue 25 (clip_hidden.cpp): a region with holes, triangulated whole.
//
// An occluder inside an element (touching none of its edges) leaves a
// ring. Cut into two strips at a whole pixel, each ear-clipped, a 64x64
// tile around a 48x48 occluder took 12 triangles; as a ring it takes 8,
// with the least edge length there is (both outlines and eight diagonals;
// llvmpipe pays 6.8 ns per pixel of triangle edge), and an element GL does
// not snap exactly, which strips could not cut, can be cut too. So the
// region is triangulated as it is: the greedy triangulation (every
// candidate diagonal, shortest first, kept when it lies inside the region
// and touches no edge kept so far) comes close to the least total edge
// length and needs no bridges between the holes and the outline.
//
// Every test is exact: the points are integers (Clipper's 2^-32 px), all
// products are taken in 128 bits. Points whose magnitude is under 2^60 keep
// every product below 2^125.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <vector>

#include "common/segments.h"
#include "scene/internal.h"

namespace depthcull::detail {

__extension__ typedef __int128 Wide;

// Exact; found by segments_touch through argument-dependent lookup.
static Wide orient(GridPoint a, GridPoint b, GridPoint c) {
    return Wide(b.x - a.x) * Wide(c.y - a.y) - Wide(b.y - a.y) * Wide(c.x - a.x);
}

namespace {

constexpr std::int64_t kMaxMagnitude = std::int64_t(1) << 60;

// p (coordinates already scaled as the contours by `scale`) strictly
// inside the closed contour c, by crossings; p lies on no edge here.
bool inside(const std::vector<GridPoint>& c, std::int64_t scale, GridPoint p) {
    bool in = false;
    const std::size_t n = c.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        const GridPoint a{c[j].x * scale, c[j].y * scale}, b{c[i].x * scale, c[i].y * scale};
        if ((a.y > p.y) != (b.y > p.y)) {
            const Wide o = orient(a, b, p);
            if (b.y > a.y ? o > 0 : o < 0) in = !in;
        }
    }
    return in;
}

bool in_region(const std::vector<std::vector<GridPoint>>& contours, std::int64_t scale, GridPoint p) {
    if (!inside(contours[0], scale, p)) return false;
    for (std::size_t h = 1; h < contours.size(); ++h)
        if (inside(contours[h], scale, p)) return false;
    return true;
}

Wide doubled_area(const std::vector<GridPoint>& c) {
    Wide sum = 0;
    for (std::size_t i = 0, j = c.size() - 1; i < c.size(); j = i++) sum += Wide(c[j].x) * Wide(c[i].y) - Wide(c[i].x) * Wide(c[j].y);
    return sum;
}

// A point other than a and b within `clearance`, or within 1/max_aspect
// of the segment's length, of the open segment a-b (within its span). In
// doubles: a threshold, not an exact test.
bool passes_near_a_point(const std::vector<GridPoint>& p, std::uint32_t i, std::uint32_t j, std::int64_t clearance, double max_aspect) {
    if (clearance <= 0 && !(max_aspect > 0)) return false;
    const GridPoint a = p[i], b = p[j];
    const double dx = double(b.x - a.x), dy = double(b.y - a.y), len2 = dx * dx + dy * dy;
    // |orient| is the distance times the length.
    const double reach = std::max(double(clearance) * std::sqrt(len2), max_aspect > 0 ? len2 / max_aspect : 0.0);
    for (std::uint32_t m = 0; m < p.size(); ++m) {
        if (m == i || m == j) continue;
        const double along = dx * double(p[m].x - a.x) + dy * double(p[m].y - a.y);
        if (along > 0 && along < len2 && std::abs(double(orient(a, b, p[m]))) < reach) return true;
    }
    return false;
}

// Each point's neighbours along its contour, ordered so that the region
// lies to the left of prev -> point -> next (an outline turning
// counterclockwise, a hole clockwise, y up), and the turn there.
struct Corner {
    std::uint32_t prev, next;
    Wide turn;
};

// Whether a diagonal from corner point v towards t starts into the region:
// strictly inside the angle the region makes at v. Near v the region is
// that angle alone (no other point is v; an edge passing through v would
// touch every diagonal from v), so a diagonal that does not start inside
// it runs along an edge or starts outside, and then, touching no edge,
// lies outside whole: the full test below refuses it either way, after
// scanning every edge. Exact, so the triangulation is the same.
bool opens_into(const std::vector<GridPoint>& p, const Corner& c, GridPoint v, GridPoint t) {
    const GridPoint u = p[c.prev], w = p[c.next];
    const bool after_in = orient(u, v, t) > 0, before_in = orient(v, w, t) > 0;
    if (c.turn > 0) return after_in && before_in; // convex: inside both edges
    if (c.turn < 0) return after_in || before_in; // reflex: outside both is outside
    // Straight on: the half plane left of it; a spike back: not decided here.
    const bool ahead = Wide(v.x - u.x) * Wide(w.x - v.x) + Wide(v.y - u.y) * Wide(w.y - v.y) > 0;
    return ahead ? after_in : true;
}

} // namespace

std::vector<std::uint32_t> triangulate_with_holes(const std::vector<std::vector<GridPoint>>& contours, std::int64_t clearance,
                                                  double max_aspect, bool cones) {
    std::vector<std::uint32_t> none;
    if (contours.empty()) return none;
    std::vector<GridPoint> p;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges; // the contours' edges, then the diagonals kept
    for (const std::vector<GridPoint>& c : contours) {
        if (c.size() < 3) return none;
        const std::uint32_t first = std::uint32_t(p.size());
        for (std::size_t i = 0; i < c.size(); ++i) {
            if (!(c[i].x > -kMaxMagnitude && c[i].x < kMaxMagnitude && c[i].y > -kMaxMagnitude && c[i].y < kMaxMagnitude)) return none;
            p.push_back(c[i]);
            edges.push_back({first + std::uint32_t(i), first + std::uint32_t((i + 1) % c.size())});
        }
    }
    const std::size_t n = p.size(), holes = contours.size() - 1;
    if (n > kMaxHoleTriangulationVertices) return none;
    // A point twice (contours touching) would need its two copies told
    // apart by their cones; the caller's strictly simple contours have none.
    {
        std::vector<std::pair<std::int64_t, std::int64_t>> sorted;
        for (const GridPoint& q : p) sorted.push_back({q.x, q.y});
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) return none;
    }
    // A contour without area has no inside to start into: no cones then.
    std::vector<Wide> areas; // per contour, doubled and signed
    std::vector<Corner> corners(n);
    for (std::size_t c = 0, first = 0; c < contours.size(); first += contours[c].size(), ++c) {
        const std::size_t m = contours[c].size();
        const Wide area = areas.emplace_back(doubled_area(contours[c]));
        cones = cones && area != 0;
        const bool left = c == 0 ? area > 0 : area < 0; // the region lies left of the contour's own order
        for (std::size_t k = 0; k < m; ++k) {
            const std::uint32_t before = std::uint32_t(first + (k + m - 1) % m), after = std::uint32_t(first + (k + 1) % m);
            Corner& corner = corners[first + k];
            corner.prev = left ? before : after;
            corner.next = left ? after : before;
            corner.turn = orient(p[corner.prev], p[first + k], p[corner.next]);
        }
    }
    std::vector<std::uint8_t> adjacent(n * n, 0);
    for (auto [a, b] : edges) adjacent[a * n + b] = adjacent[b * n + a] = 1;

    // Candidates shortest first; ties by index, so the result is the same
    // on every machine.
    std::vector<std::tuple<Wide, std::uint32_t, std::uint32_t>> candidates;
    for (std::uint32_t i = 0; i < n; ++i)
        for (std::uint32_t j = i + 1; j < n; ++j) {
            if (adjacent[i * n + j]) continue;
            if (cones && (!opens_into(p, corners[i], p[i], p[j]) || !opens_into(p, corners[j], p[j], p[i]))) continue;
            const Wide dx = p[j].x - p[i].x, dy = p[j].y - p[i].y;
            candidates.emplace_back(dx * dx + dy * dy, i, j);
        }
    std::sort(candidates.begin(), candidates.end());
    // A triangulation of n points with h holes has n + 3h - 3 diagonals.
    const std::size_t wanted = n + 3 * holes - 3;
    std::size_t kept = 0;
    for (const auto& [length, i, j] : candidates) {
        if (kept == wanted) break;
        const GridPoint a = p[i], b = p[j];
        bool clear = true;
        for (std::size_t e = 0; e < edges.size() && clear; ++e) {
            const auto [c, d] = edges[e];
            const bool at_i = c == i || d == i, at_j = c == j || d == j;
            if (!at_i && !at_j) {
                clear = !segments_touch(a, b, p[c], p[d]);
                continue;
            }
            // Sharing an end: only a collinear edge along the diagonal meets it elsewhere.
            const std::uint32_t shared = at_i ? i : j, other_end = c == shared ? d : c, far_end = shared == i ? j : i;
            const GridPoint s = p[shared], o = p[other_end], f = p[far_end];
            if (orient(s, f, o) == 0 && Wide(f.x - s.x) * Wide(o.x - s.x) + Wide(f.y - s.y) * Wide(o.y - s.y) > 0) clear = false;
        }
        // Touching nothing, the open diagonal lies wholly inside or outside.
        if (!clear || !in_region(contours, 2, {a.x + b.x, a.y + b.y}) || passes_near_a_point(p, i, j, clearance, max_aspect)) continue;
        edges.push_back({i, j});
        adjacent[i * n + j] = adjacent[j * n + i] = 1;
        ++kept;
    }
    if (kept != wanted) return none;

    // The faces: 3-cycles with no point inside and their centre in the region
    // (a triangular hole is a 3-cycle too).
    const Wide outer = areas[0];
    Wide expected = outer < 0 ? -outer : outer;
    for (std::size_t h = 1; h < contours.size(); ++h) expected -= areas[h] < 0 ? -areas[h] : areas[h];
    // Each face is found once: from its two lowest points' edge.
    std::vector<std::uint32_t> triangles;
    Wide covered = 0;
    for (const auto& [i, j] : edges) {
        const std::uint32_t lo = std::min(i, j), hi = std::max(i, j);
        for (std::uint32_t k = hi + 1; k < n; ++k) {
            if (!adjacent[lo * n + k] || !adjacent[hi * n + k]) continue;
            const Wide o = orient(p[lo], p[hi], p[k]);
            if (o == 0) continue;
            bool empty = true;
            for (std::uint32_t m = 0; m < n && empty; ++m) {
                if (m == lo || m == hi || m == k) continue;
                const Wide o1 = orient(p[lo], p[hi], p[m]), o2 = orient(p[hi], p[k], p[m]), o3 = orient(p[k], p[lo], p[m]);
                empty = !(o > 0 ? (o1 > 0 && o2 > 0 && o3 > 0) : (o1 < 0 && o2 < 0 && o3 < 0));
            }
            if (!empty || !in_region(contours, 3, {p[lo].x + p[hi].x + p[k].x, p[lo].y + p[hi].y + p[k].y})) continue;
            // The triangles turn as the outline does.
            if ((o > 0) == (outer > 0)) triangles.insert(triangles.end(), {lo, hi, k});
            else triangles.insert(triangles.end(), {lo, k, hi});
            covered += o < 0 ? -o : o;
        }
    }
    return covered == expected && triangles.size() == 3 * (n + 2 * holes - 2) ? triangles : none;
}

} // namespace depthcull::detail
