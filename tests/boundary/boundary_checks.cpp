#include "boundary_checks.h"

#include <cmath>

namespace depthcull::test {

namespace {

bool on_grid(double v, Filter f) {
    double s = f == Filter::linear ? 2.0 : 1.0;
    return std::floor(v * s) == v * s;
}

bool boxes_apart(const Polygon& a, const Polygon& b) {
    Box x = bounds({a}), y = bounds({b});
    return x.x1 < y.x0 || y.x1 < x.x0 || x.y1 < y.y0 || y.y1 < x.y0;
}

// Polygons share no point: no edges touch and neither has a vertex inside
// the other (exact: grid coordinates).
bool polygons_disjoint(const Polygon& a, const Polygon& b) {
    if (boxes_apart(a, b)) return true;
    for (std::size_t i = 0; i < a.size(); ++i)
        for (std::size_t j = 0; j < b.size(); ++j) {
            Polygon quad{a[i], a[(i + 1) % a.size()], b[j], b[(j + 1) % b.size()]};
            Vec2 p = quad[0], q = quad[1], r = quad[2], s = quad[3];
            double o1 = orient(p, q, r), o2 = orient(p, q, s), o3 = orient(r, s, p), o4 = orient(r, s, q);
            auto within = [](Vec2 u, Vec2 v, Vec2 w) {
                return std::min(u.x, v.x) <= w.x && w.x <= std::max(u.x, v.x) && std::min(u.y, v.y) <= w.y &&
                       w.y <= std::max(u.y, v.y);
            };
            if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return false;
            if ((o1 == 0 && within(p, q, r)) || (o2 == 0 && within(p, q, s)) || (o3 == 0 && within(r, s, p)) ||
                (o4 == 0 && within(r, s, q)))
                return false;
        }
    // No edge contact: disjoint unless one lies inside the other.
    auto inside = [](const Polygon& poly, Vec2 v) {
        bool in = false;
        for (std::size_t i = 0, n = poly.size(); i < n; ++i) {
            Vec2 a = poly[i], c = poly[(i + 1) % n];
            if ((a.y > v.y) != (c.y > v.y)) {
                double o = orient(a, c, v);
                if (c.y > a.y ? o > 0 : o < 0) in = !in;
            }
        }
        return in;
    };
    return !inside(a, b[0]) && !inside(b, a[0]);
}

} // namespace

std::string boundary_guarantee_failure(ImageView image, Rect rect, const std::vector<Polygon>& polygons,
                                       const FilteredBoundary& options) {
    const int max_vertices = std::max(4, options.max_vertices);
    for (std::size_t k = 0; k < polygons.size(); ++k) {
        const Polygon& p = polygons[k];
        std::string at = "polygon " + std::to_string(k) + ": ";
        if (p.size() < 3) return at + "fewer than 3 vertices";
        if (int(p.size()) > max_vertices) return at + std::to_string(p.size()) + " vertices";
        if (!is_simple(p)) return at + "not simple";
        if (signed_area(p) <= 0) return at + "not clockwise";
        for (std::size_t i = 0; i < p.size(); ++i) {
            Vec2 a = p[(i + p.size() - 1) % p.size()], v = p[i], b = p[(i + 1) % p.size()];
            if (orient(a, v, b) == 0) return at + "straight angle or repeated vertex";
            if (!on_grid(v.x, options.filter) || !on_grid(v.y, options.filter)) return at + "vertex off the grid";
            if (v.x < rect.x || v.y < rect.y || v.x > rect.x + rect.w || v.y > rect.y + rect.h)
                return at + "vertex outside the rect";
        }
        for (std::size_t j = k + 1; j < polygons.size(); ++j)
            if (!polygons_disjoint(p, polygons[j]))
                return at + "overlaps or touches polygon " + std::to_string(j);
    }
    std::int64_t missing = count_uncontained_texels(image, rect, polygons, options.filter);
    if (missing) return std::to_string(missing) + " uncontained texels";
    if (!options.split_parts && polygons.size() > 1) return "split despite split_parts = false";
    return "";
}

} // namespace depthcull::test
