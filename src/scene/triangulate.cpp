// Paper 2.3.3 AddPolygon / FindPolygonEar: ear clipping with Held's ear
// conditions (FIST). Vertices are texel-grid points (integers or halves),
// so every orientation test here is exact in doubles.
//
// Robustness to collinear vertices: an ear needs a strictly convex tip, and
// no other remaining vertex may lie in the closed ear triangle (a vertex on
// the diagonal would make the rest touch itself). When no such ear exists
// the polygon still has a straight-angle vertex, which is removed without
// a triangle (it adds no area). A last resort for invalid input (not
// simple) clips the first convex vertex so the loop always ends.
#include <cstdint>
#include <vector>

#include "depthcull/scene.h"

namespace depthcull {

namespace {

// p in the closed triangle (a, b, c) of orientation `sign`.
bool in_closed_triangle(Vec2 p, Vec2 a, Vec2 b, Vec2 c, double sign) {
    return sign * orient(a, b, p) >= 0 && sign * orient(b, c, p) >= 0 && sign * orient(c, a, p) >= 0;
}

} // namespace

std::vector<std::uint32_t> triangulate_polygon(const Polygon& polygon) {
    std::vector<std::uint32_t> triangles;
    if (polygon.size() < 3) return triangles;
    // Clip ears turning the polygon's own way, so either orientation works.
    const double sign = signed_area(polygon) < 0 ? -1.0 : 1.0;
    std::vector<std::uint32_t> left(polygon.size());
    for (std::size_t i = 0; i < left.size(); ++i) left[i] = std::uint32_t(i);
    auto at = [&](std::size_t k) { return polygon[left[k % left.size()]]; };

    while (left.size() > 3) {
        const std::size_t n = left.size();
        std::size_t ear = n;
        for (std::size_t k = 0; k < n && ear == n; ++k) {
            Vec2 a = at(k + n - 1), b = at(k), c = at(k + 1);
            if (sign * orient(a, b, c) <= 0) continue; // straight or reflex
            bool empty = true;
            for (std::size_t m = 0; m < n && empty; ++m) {
                if (m == k || m == (k + 1) % n || m == (k + n - 1) % n) continue;
                Vec2 v = at(m);
                if (v == a || v == c) continue; // a repeated point is no obstacle
                empty = !in_closed_triangle(v, a, b, c, sign);
            }
            if (empty) ear = k;
        }
        if (ear == n) {
            std::size_t straight = n;
            for (std::size_t k = 0; k < n && straight == n; ++k)
                if (orient(at(k + n - 1), at(k), at(k + 1)) == 0) straight = k;
            if (straight != n) {
                left.erase(left.begin() + std::ptrdiff_t(straight));
                continue;
            }
            for (std::size_t k = 0; k < n && ear == n; ++k)
                if (sign * orient(at(k + n - 1), at(k), at(k + 1)) > 0) ear = k;
            if (ear == n) break; // nothing with area left
        }
        triangles.insert(triangles.end(), {left[(ear + n - 1) % n], left[ear], left[(ear + 1) % n]});
        left.erase(left.begin() + std::ptrdiff_t(ear));
    }
    if (left.size() == 3 && orient(polygon[left[0]], polygon[left[1]], polygon[left[2]]) != 0)
        triangles.insert(triangles.end(), {left[0], left[1], left[2]});
    return triangles;
}

} // namespace depthcull
