#include "depthcull/geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/segments.h"

namespace depthcull {

double signed_area(const Polygon& p) {
    // Shoelace with the division the paper's CalcPolygonArea lacks (errata).
    double twice = 0;
    for (std::size_t i = 0, n = p.size(); i < n; ++i) {
        const Vec2& a = p[i];
        const Vec2& b = p[(i + 1) % n];
        twice += a.x * b.y - a.y * b.x;
    }
    return twice / 2;
}

double total_area(const std::vector<Polygon>& polygons) {
    double sum = 0;
    for (const auto& p : polygons) sum += area(p);
    return sum;
}

bool is_simple(const Polygon& p) {
    std::size_t n = p.size();
    if (n < 3) return false;
    for (std::size_t i = 0; i < n; ++i)
        if (p[i] == p[(i + 1) % n]) return false;
    for (std::size_t i = 0; i < n; ++i) {
        Vec2 a = p[i], b = p[(i + 1) % n];
        for (std::size_t j = i + 1; j < n; ++j) {
            Vec2 c = p[j], d = p[(j + 1) % n];
            bool adjacent = j == i + 1 || (i == 0 && j == n - 1);
            if (!adjacent) {
                if (segments_touch(a, b, c, d)) return false;
                continue;
            }
            // Adjacent edges may only share their common vertex: reject
            // a fold-back where they overlap along a line.
            Vec2 shared = (j == i + 1) ? b : a;
            Vec2 other1 = (j == i + 1) ? a : b;
            Vec2 other2 = (j == i + 1) ? d : c;
            if (orient(shared, other1, other2) == 0) {
                Vec2 u = other1 - shared, v = other2 - shared;
                if (u.x * v.x + u.y * v.y > 0) return false;
            }
        }
    }
    return true;
}

bool is_convex(const Polygon& p) {
    std::size_t n = p.size();
    if (n < 3 || signed_area(p) <= 0) return false;
    for (std::size_t i = 0; i < n; ++i)
        if (orient(p[i], p[(i + 1) % n], p[(i + 2) % n]) < 0) return false;
    return is_simple(p);
}

Box bounds(const std::vector<Polygon>& polygons) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    Box b{inf, inf, -inf, -inf};
    bool any = false;
    for (const auto& p : polygons)
        for (const Vec2& v : p) {
            b.x0 = std::min(b.x0, v.x);
            b.y0 = std::min(b.y0, v.y);
            b.x1 = std::max(b.x1, v.x);
            b.y1 = std::max(b.y1, v.y);
            any = true;
        }
    return any ? b : Box{};
}

} // namespace depthcull
