// depthcull: polygons in texel space.
//
// Vertices are doubles so one type carries every coordinate we emit, but the
// stages place them on the texel grid (integers, or halves where a polygon is
// pulled half a texel inward) so that doubles hold them exactly and the
// predicates below are exact for them.
#pragma once

#include <cstdint>
#include <vector>

namespace depthcull {

struct Vec2 {
    double x = 0, y = 0;
    friend bool operator==(const Vec2&, const Vec2&) = default;
};

// Exact integer division rounding toward minus / plus infinity (d != 0):
// the grid arithmetic of both analysis stages (one definition for both).
inline std::int64_t floor_div(std::int64_t n, std::int64_t d) {
    if (d < 0) n = -n, d = -d;
    const std::int64_t q = n / d;
    return (n % d != 0 && n < 0) ? q - 1 : q;
}
inline std::int64_t ceil_div(std::int64_t n, std::int64_t d) { return -floor_div(-n, d); }

inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }

// Polygons are simple and listed clockwise as seen with y pointing down,
// which is a positive signed_area().
using Polygon = std::vector<Vec2>;

inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
// > 0 when a -> b -> c turns clockwise (y down), 0 when collinear.
inline double orient(Vec2 a, Vec2 b, Vec2 c) { return cross(b - a, c - a); }

// Shoelace area, positive for clockwise (y down) polygons. Errata: the
// paper's CalcPolygonArea lacks the division by two.
double signed_area(const Polygon& polygon);
inline double area(const Polygon& polygon) {
    double a = signed_area(polygon);
    return a < 0 ? -a : a;
}
double total_area(const std::vector<Polygon>& polygons);

// True when no two non-adjacent edges touch and adjacent edges meet only at
// their shared vertex (a simple polygon, possibly with collinear vertices).
bool is_simple(const Polygon& polygon);
bool is_convex(const Polygon& polygon); // clockwise, no reflex vertex

// Axis-aligned bounds of a polygon set.
struct Box {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
};
Box bounds(const std::vector<Polygon>& polygons);

} // namespace depthcull
