// Internal to the core: the segment-touch test the polygon predicates and
// triangulations use (boundary's integer is_simple, the double is_simple
// of geometry.cpp, triangulate and triangulate_holes).
#pragma once

namespace depthcull {

// Closed segments ab and cd share at least one point. P is any point type
// with x and y whose orient(a, b, c) (found by argument-dependent lookup)
// is exact: the integer grid of src/boundary, or Vec2 on the texel grid
// (products of small integers or halves are exact in double).
template <class P>
bool segments_touch(P a, P b, P c, P d) {
    // Closed segments whose boxes are apart share no point: most pairs a
    // triangulation tests end here, before four (128-bit) orientations.
    auto lo = [](auto u, auto v) { return u < v ? u : v; };
    auto hi = [](auto u, auto v) { return u < v ? v : u; };
    if (hi(a.x, b.x) < lo(c.x, d.x) || hi(c.x, d.x) < lo(a.x, b.x) || hi(a.y, b.y) < lo(c.y, d.y) || hi(c.y, d.y) < lo(a.y, b.y))
        return false;
    auto sign = [](auto v) { return (v > 0) - (v < 0); };
    // p, known collinear with ab, lies within it.
    auto on_segment = [&](P s, P e, P p) { return lo(s.x, e.x) <= p.x && p.x <= hi(s.x, e.x) && lo(s.y, e.y) <= p.y && p.y <= hi(s.y, e.y); };
    const int o1 = sign(orient(a, b, c)), o2 = sign(orient(a, b, d));
    const int o3 = sign(orient(c, d, a)), o4 = sign(orient(c, d, b));
    if (o1 * o2 < 0 && o3 * o4 < 0) return true; // a proper crossing
    return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) || (o3 == 0 && on_segment(c, d, a)) ||
           (o4 == 0 && on_segment(c, d, b));
}

} // namespace depthcull
