// Beyond the paper: a skirt of triangles around boundary polygons
// (ReconstructOptions::coverage_margin), so that GL's vertex snapping
// cannot leave out a pixel whose texel lies inside a polygon.
//
// Why a skirt rather than moving the polygon's vertices outward: the
// polygon's own triangles stay exactly as without a margin, and the skirt
// lies wholly outside the polygon, where every texel is transparent (paper
// 2.1's guarantee) or outside the rect (the renderer's rect test): its
// fragments change nothing, however the skirt's triangles overlap each
// other. Moved vertices could flip thin ear-clipped triangles and blend
// inside texels twice.
#include <algorithm>
#include <cmath>

#include "scene/internal.h"

namespace depthcull::detail {

namespace {

struct Screen {
    double x, y;
};

double distance_to_segment(Screen p, Screen a, Screen b) {
    const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
    double t = len2 > 0 ? ((p.x - a.x) * dx + (p.y - a.y) * dy) / len2 : 0;
    t = std::clamp(t, 0.0, 1.0);
    return std::hypot(a.x + t * dx - p.x, a.y + t * dy - p.y);
}

// Smallest distance from a vertex of p to an edge of q (p == q: to an edge
// not incident to the vertex). For simple polygons that do not cross, the
// boundaries' distance is attained at such a pair.
double vertex_edge_distance(const std::vector<Screen>& p, const std::vector<Screen>& q, bool same) {
    double best = INFINITY;
    const std::size_t n = q.size();
    for (std::size_t i = 0; i < p.size(); ++i) {
        for (std::size_t k = 0; k < n; ++k) {
            if (same && (k == i || (k + 1) % n == i)) continue;
            best = std::min(best, distance_to_segment(p[i], q[k], q[(k + 1) % n]));
        }
    }
    return best;
}

// Polygons (or parts of one) closer than the skirt reaches would get each
// other's skirt over their inside texels: 0 for those, 1 for the others.
std::vector<std::uint8_t> far_apart(const std::vector<std::vector<Screen>>& screen, double reach) {
    std::vector<std::uint8_t> grow(screen.size(), 1);
    for (std::size_t a = 0; a < screen.size(); ++a) {
        if (screen[a].size() < 3) grow[a] = 0;
        for (std::size_t b = a; b < screen.size(); ++b) {
            const bool same = a == b;
            if (vertex_edge_distance(screen[a], screen[b], same) < reach ||
                (!same && vertex_edge_distance(screen[b], screen[a], false) < reach))
                grow[a] = grow[b] = 0;
        }
    }
    return grow;
}

// The skirt of one polygon p (screen coordinates) `margin` wide: vertices
// through add_vertex, triangles into indices. False (nothing added) for a
// polygon of no area or with a corner too sharp for a miter.
template <class AddVertex>
bool add_polygon_skirt(const std::vector<Screen>& p, double margin, AddVertex add_vertex, std::vector<std::uint32_t>& indices) {
    const std::size_t n = p.size();
    double area = 0;
    for (std::size_t i = 0; i < n; ++i) area += p[i].x * p[(i + 1) % n].y - p[(i + 1) % n].x * p[i].y;
    if (!(area != 0)) return false;
    const double side = area > 0 ? 1 : -1;
    // Outward unit normal of edge i (p[i] -> p[i+1]); zero for a
    // zero-length edge.
    std::vector<Screen> normal(n);
    for (std::size_t i = 0; i < n; ++i) {
        const double dx = p[(i + 1) % n].x - p[i].x, dy = p[(i + 1) % n].y - p[i].y, len = std::hypot(dx, dy);
        normal[i] = len > 0 ? Screen{side * dy / len, -side * dx / len} : Screen{0, 0};
    }
    // Reflex corners: the skirts of the two edges meet on the corner's
    // exterior bisector, at the offset lines' crossing (the miter), so
    // neither reaches into the polygon. Ending them square instead
    // would cross the other edge where the exterior angle is below 90
    // degrees and run along it at 90, where GL's snapping may then
    // cover an inside pixel twice. A corner so sharp that the miter runs
    // far out leaves the polygon without a skirt.
    std::vector<std::uint8_t> reflex(n, 0);
    std::vector<Screen> miter(n);
    bool sharp = false;
    for (std::size_t i = 0; i < n; ++i) {
        const Screen n1 = normal[(i + n - 1) % n], n2 = normal[i];
        const double cross = n1.x * n2.y - n1.y * n2.x, dot = n1.x * n2.x + n1.y * n2.y;
        if (!(cross * side < 0)) continue;
        if (dot < -0.8) sharp = true;
        reflex[i] = 1;
        miter[i] = {margin * (n1.x + n2.x) / (1 + dot), margin * (n1.y + n2.y) / (1 + dot)};
    }
    if (sharp) return false;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        const Screen a = p[i], b = p[j], m = normal[i];
        if (m.x == 0 && m.y == 0) continue;
        const Screen da = reflex[i] ? miter[i] : Screen{margin * m.x, margin * m.y};
        const Screen db = reflex[j] ? miter[j] : Screen{margin * m.x, margin * m.y};
        const std::uint32_t ia = add_vertex(a), ib = add_vertex(b);
        const std::uint32_t ib2 = add_vertex({b.x + db.x, b.y + db.y});
        const std::uint32_t ia2 = add_vertex({a.x + da.x, a.y + da.y});
        indices.insert(indices.end(), {ia, ib, ib2, ia, ib2, ia2});
    }
    // Convex corners: a fan from the previous edge's normal to the
    // next's, in steps of at most 45 degrees at radius margin /
    // cos(step / 2), covers every point within the margin of the corner.
    for (std::size_t i = 0; i < n; ++i) {
        const Screen n1 = normal[(i + n - 1) % n], n2 = normal[i];
        if ((n1.x == 0 && n1.y == 0) || (n2.x == 0 && n2.y == 0)) continue;
        const double turn = std::atan2(n1.x * n2.y - n1.y * n2.x, n1.x * n2.x + n1.y * n2.y);
        // Normals turn with the traversal at convex corners (the same sign as area).
        if (!(turn * side > 0)) continue;
        const int steps = std::max(1, int(std::ceil(std::abs(turn) / (3.14159265358979323846 / 4))));
        const double step = turn / steps, radius = margin / std::cos(step / 2);
        const double base = std::atan2(n1.y, n1.x);
        const std::uint32_t centre = add_vertex(p[i]);
        std::uint32_t last = add_vertex({p[i].x + radius * std::cos(base), p[i].y + radius * std::sin(base)});
        for (int s = 1; s <= steps; ++s) {
            const double angle = base + step * s;
            const std::uint32_t next = add_vertex({p[i].x + radius * std::cos(angle), p[i].y + radius * std::sin(angle)});
            indices.insert(indices.end(), {centre, last, next});
            last = next;
        }
    }
    return true;
}

} // namespace

std::vector<std::uint8_t> MeshBuilder::add_skirts(Draw& d, std::uint32_t element, const std::vector<Polygon>& polygons, float z) {
    if (!(margin_ > 0) || !std::isfinite(margin_)) return std::vector<std::uint8_t>(polygons.size(), 0);
    const Element& e = scene_.elements[element];
    const SceneImage& img = scene_.images[std::size_t(e.image)];
    const TexelMap map = texel_map(e);
    const double iw = 1.0 / img.width, ih = 1.0 / img.height;
    std::vector<std::vector<Screen>> screen(polygons.size());
    for (std::size_t k = 0; k < polygons.size(); ++k)
        for (const Vec2& v : polygons[k]) {
            Vec2 s = apply(e.transform, {v.x - e.rect.x, v.y - e.rect.y});
            screen[k].push_back({s.x, s.y});
        }
    std::vector<std::uint8_t> grow = far_apart(screen, 3 * margin_);

    note_element(d, element);
    auto add_vertex = [&](Screen s) {
        const double u = map.u0 + map.ux * s.x + map.uy * s.y, v = map.v0 + map.vx * s.x + map.vy * s.y;
        d.vertices.insert(d.vertices.end(),
                          {float(s.x), float(s.y), z, float(u * iw), float(v * ih), e.color[0], e.color[1], e.color[2], e.color[3]});
        return std::uint32_t(d.vertex_count() - 1);
    };
    for (std::size_t k = 0; k < screen.size(); ++k) {
        if (!grow[k]) continue;
        grow[k] = add_polygon_skirt(screen[k], margin_, add_vertex, d.indices);
    }
    return grow;
}

} // namespace depthcull::detail
