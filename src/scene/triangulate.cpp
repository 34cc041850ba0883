// Paper 2.3.3 AddPolygon / FindPolygonEar: ear clipping with Held's ear
// conditions (FIST). Vertices are texel-grid points (integers or halves),
// so every orientation test here is exact in doubles.
//
// Issue 25: where the vertices lie on a fine dyadic grid (the texel grid,
// cover's 1/16 grid) and are few, the polygon is first triangulated with
// the least total diagonal length instead (dynamic programming over
// sub-polygons, exact tests). Every triangulation of the same polygon
// covers the same pixel centres once, so the picture cannot change; but
// a renderer that shades whole 4x4 blocks pays for every edge along its
// length (llvmpipe: 6.8 ns per pixel of triangle perimeter, as much as
// 1.4 blended fragments), and ear clipping's long thin fans pay most.
//
// Robustness to collinear vertices: an ear needs a strictly convex tip, and
// no other remaining vertex may lie in the closed ear triangle (a vertex on
// the diagonal would make the rest touch itself). When no such ear exists
// the polygon still has a straight-angle vertex, which is removed without
// a triangle (it adds no area). A last resort for invalid input (not
// simple) clips the first convex vertex so the loop always ends.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "common/segments.h"
#include "depthcull/scene.h"

namespace depthcull {

namespace {

// p in the closed triangle (a, b, c) of orientation `sign`.
bool in_closed_triangle(Vec2 p, Vec2 a, Vec2 b, Vec2 c, double sign) {
    return sign * orient(a, b, p) >= 0 && sign * orient(b, c, p) >= 0 && sign * orient(c, a, p) >= 0;
}

// The least-perimeter triangulation is tried up to this many vertices
// (its tests grow as n^3: measured 5 us for 10 vertices, the default
// budget, 0.16 ms for 32 and 1.2 ms for 64, once per polygon of a run).
constexpr std::size_t kMaxShortestVertices = 64;

// Every coordinate a multiple of 2^-8 under 2^16 in magnitude: then every
// orient() below (products of differences under 2^17, on a 2^-8 grid) is
// exact in doubles.
bool on_exact_grid(const Polygon& polygon) {
    for (const Vec2& v : polygon)
        for (double c : {v.x, v.y}) {
            if (!(std::abs(c) < 65536.0)) return false;
            const double scaled = c * 256.0;
            if (scaled != std::floor(scaled)) return false;
        }
    return true;
}

// m strictly between p and q on the segment p-q.
bool strictly_on_segment(Vec2 m, Vec2 p, Vec2 q) {
    if (orient(p, q, m) != 0 || m == p || m == q) return false;
    return std::min(p.x, q.x) <= m.x && m.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= m.y && m.y <= std::max(p.y, q.y);
}

// p strictly inside the simple polygon (not on it), by crossings with exact
// orientation tests (no division).
bool inside(const Polygon& polygon, Vec2 p) {
    bool in = false;
    const std::size_t n = polygon.size();
    for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
        const Vec2 a = polygon[j], b = polygon[i];
        if ((a.y > p.y) != (b.y > p.y)) {
            // The edge crosses the horizontal line through p; right of p?
            const double o = orient(a, b, p);
            if (b.y > a.y ? o > 0 : o < 0) in = !in;
        }
    }
    return in;
}

// Least total diagonal length over the vertices `v` (indices into
// polygon, straight-angle vertices already left out), or empty when no
// triangulation with positive-area triangles exists.
std::vector<std::uint32_t> shortest_triangulation(const Polygon& polygon, const std::vector<std::uint32_t>& v, double sign) {
    const std::size_t n = v.size();
    auto at = [&](std::size_t k) { return polygon[v[k]]; };
    // ok[i][j]: i-j is an edge or a diagonal inside the polygon.
    std::vector<std::uint8_t> ok(n * n, 0);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            if (j == i + 1 || (i == 0 && j == n - 1)) {
                ok[i * n + j] = 1;
                continue;
            }
            const Vec2 p = at(i), q = at(j);
            if (p == q) continue;
            bool clear = true;
            for (std::size_t m = 0; m < n && clear; ++m) {
                const std::size_t m2 = (m + 1) % n;
                if (m != i && m != j && strictly_on_segment(at(m), p, q)) clear = false;
                // An edge not at i or j: the diagonal may not even touch it.
                if (m == i || m == j || m2 == i || m2 == j) continue;
                if (segments_touch(p, q, at(m), at(m2))) clear = false;
            }
            // Crossing nothing, the diagonal lies wholly inside or outside.
            ok[i * n + j] = clear && inside(polygon, {(p.x + q.x) / 2, (p.y + q.y) / 2});
        }
    // best[i][j]: the sub-polygon i..j closed by the diagonal i-j.
    std::vector<double> best(n * n, INFINITY);
    std::vector<std::uint32_t> pick(n * n, 0);
    for (std::size_t i = 0; i + 1 < n; ++i) best[i * n + i + 1] = 0;
    for (std::size_t len = 2; len < n; ++len)
        for (std::size_t i = 0; i + len < n; ++i) {
            const std::size_t j = i + len;
            if (!ok[i * n + j]) continue;
            for (std::size_t k = i + 1; k < j; ++k) {
                if (!ok[i * n + k] || !ok[k * n + j] || !(sign * orient(at(i), at(k), at(j)) > 0)) continue;
                const double c = best[i * n + k] + best[k * n + j] + (k > i + 1 ? std::hypot(at(k).x - at(i).x, at(k).y - at(i).y) : 0.0) +
                                 (j > k + 1 ? std::hypot(at(j).x - at(k).x, at(j).y - at(k).y) : 0.0);
                if (c < best[i * n + j]) best[i * n + j] = c, pick[i * n + j] = std::uint32_t(k);
            }
        }
    std::vector<std::uint32_t> triangles;
    if (!std::isfinite(best[n - 1])) return triangles;
    std::vector<std::pair<std::size_t, std::size_t>> todo{{0, n - 1}};
    while (!todo.empty()) {
        const auto [i, j] = todo.back();
        todo.pop_back();
        if (j < i + 2) continue;
        const std::size_t k = pick[i * n + j];
        triangles.insert(triangles.end(), {v[i], v[k], v[j]});
        todo.push_back({k, j});
        todo.push_back({i, k});
    }
    return triangles;
}

} // namespace

std::vector<std::uint32_t> triangulate_polygon(const Polygon& polygon) {
    std::vector<std::uint32_t> triangles;
    if (polygon.size() < 3) return triangles;
    // Triangles turn the polygon's own way, so either orientation works.
    const double sign = signed_area(polygon) < 0 ? -1.0 : 1.0;
    if (polygon.size() > 3 && polygon.size() <= kMaxShortestVertices && on_exact_grid(polygon)) {
        // Straight-angle vertices add no area; left out as the ear clipping
        // below leaves them (one triangle fewer each).
        std::vector<std::uint32_t> kept;
        const std::size_t n = polygon.size();
        for (std::size_t i = 0; i < n; ++i)
            if (orient(polygon[(i + n - 1) % n], polygon[i], polygon[(i + 1) % n]) != 0) kept.push_back(std::uint32_t(i));
        if (kept.size() < 3) return triangles;
        triangles = shortest_triangulation(polygon, kept, sign);
        if (!triangles.empty()) return triangles;
    }
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
