// Beyond the paper: the texel margin (ReconstructOptions::texel_margin)
// that lets a plain renderer (texture x colour, no per-element tests, e.g.
// depthcull::runtime or an engine's sprite shader) draw the optimized
// meshes exactly like overpaint.
//
// GL snaps vertices (llvmpipe to 1/256 pixel), so a pixel centre that close
// to a polygon edge may fall on either side of it. Polygon edges lie on
// texel edges, so such a centre shows a texel next to the edge: with
// boundary polygons, possibly a non-transparent one just inside that the
// optimized frame leaves out; with opaque polygons, possibly a non-opaque
// one just outside that the opaque pass writes with blending off. Hence:
// - boundary polygons get a skirt, in texel space, `margin` wide around
//   them and clipped to the element's rect. It lies outside the polygon,
//   where every texel is transparent (paper 2.1's guarantee), so its
//   fragments leave the frame as it is in every blend mode, however its
//   pieces overlap; clipped, it never samples past the rect (the next atlas
//   frame), and the rect's own edges stay overpaint's.
//   Elements placed so that GL does not snap their vertices at all (tiles:
//   snaps_exactly) need no skirt.
// - opaque polygons (convex) are pulled `margin` inward, so every pixel the
//   opaque pass may cover samples a texel its polygon covered (also a pixel
//   centre exactly on the polygon's edge, which the fill rule may give it).
// Why texel space: the margin must beat the snapping after the element's
// scale. 1/32 texel is 1/256 pixel at a scale of 1/8, still twice
// llvmpipe's worst snapping error (1/512 pixel per coordinate), and at
// scale 1 it costs the opaque pass a 1/32-pixel strip per edge.
#include <algorithm>
#include <array>
#include <cmath>

#include "scene/internal.h"
#include "scene/placement.h"

namespace depthcull::detail {

namespace {

// Sutherland-Hodgman against one axis-aligned half plane: keeps points
// with sign * (coord - bound) >= 0, coord = x (axis 0) or y (axis 1).
Polygon clip(const Polygon& in, int axis, double bound, double sign) {
    Polygon out;
    const std::size_t n = in.size();
    auto inside = [&](const Vec2& p) { return sign * ((axis == 0 ? p.x : p.y) - bound) >= 0; };
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2& a = in[i];
        const Vec2& b = in[(i + 1) % n];
        const bool ia = inside(a), ib = inside(b);
        if (ia) out.push_back(a);
        if (ia != ib) {
            const double ca = axis == 0 ? a.x : a.y, cb = axis == 0 ? b.x : b.y;
            const double t = (bound - ca) / (cb - ca);
            Vec2 p = a + t * (b - a);
            (axis == 0 ? p.x : p.y) = bound; // exactly on the rect edge
            out.push_back(p);
        }
    }
    return out;
}

Polygon clip_to_rect(Polygon p, const Rect& r) {
    p = clip(p, 0, r.x, 1);
    if (!p.empty()) p = clip(p, 0, double(r.x) + r.w, -1);
    if (!p.empty()) p = clip(p, 1, r.y, 1);
    if (!p.empty()) p = clip(p, 1, double(r.y) + r.h, -1);
    return p;
}

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
    const Vec2 d = b - a;
    const double len2 = d.x * d.x + d.y * d.y;
    const double t = len2 > 0 ? std::clamp(((p.x - a.x) * d.x + (p.y - a.y) * d.y) / len2, 0.0, 1.0) : 0.0;
    return std::hypot(a.x + t * d.x - p.x, a.y + t * d.y - p.y);
}

// Smallest distance from a vertex of p to an edge of q (not incident to
// the vertex when p == q).
double vertex_edge_distance(const Polygon& p, const Polygon& q, bool same) {
    double best = INFINITY;
    const std::size_t n = q.size();
    for (std::size_t i = 0; i < p.size(); ++i)
        for (std::size_t k = 0; k < n; ++k) {
            if (same && (k == i || (k + 1) % n == i)) continue;
            best = std::min(best, distance_to_segment(p[i], q[k], q[(k + 1) % n]));
        }
    return best;
}

// Outward unit normal of edge i of a clockwise (y down) polygon; zero for
// a zero-length edge.
Vec2 outward_normal(const Polygon& p, std::size_t i) {
    const Vec2 d = p[(i + 1) % p.size()] - p[i];
    const double len = std::hypot(d.x, d.y);
    return len > 0 ? Vec2{d.y / len, -d.x / len} : Vec2{0, 0};
}

} // namespace

// True when GL rasterizes the element's polygons without snapping error:
// a transform of power-of-two scales (1/8 .. 8) and quarter turns or
// flips, moved by a multiple of 1/256 pixel. Polygon vertices (on the half
// texel grid) then land exactly on GL's 1/256 subpixel grid (llvmpipe; 8
// subpixel bits is what D3D11-class hardware guarantees) and in a float, so
// coverage is decided exactly, as in overpaint: no skirt needed. That is
// every tile of a tile map, at no cost in triangles.
bool snaps_exactly(const std::array<double, 6>& m) {
    auto power_of_two_or_zero = [](double a) {
        if (a == 0) return true;
        int exponent = 0;
        const double mantissa = std::frexp(std::abs(a), &exponent); // a = mantissa * 2^exponent, mantissa in [0.5, 1)
        return mantissa == 0.5 && exponent >= -2 && exponent <= 4;  // 1/8 .. 8
    };
    auto on_subpixel_grid = [](double t) { return std::abs(t) < 8192 && std::floor(t * 256) == t * 256; };
    const bool axis_aligned = (m[1] == 0 && m[2] == 0) || (m[0] == 0 && m[3] == 0);
    return axis_aligned && power_of_two_or_zero(m[0]) && power_of_two_or_zero(m[1]) && power_of_two_or_zero(m[2]) &&
           power_of_two_or_zero(m[3]) && on_subpixel_grid(m[4]) && on_subpixel_grid(m[5]);
}

void MeshBuilder::add_convex_piece(Draw& d, std::uint32_t element, const Polygon& piece, float z) {
    const Polygon p = clip_to_rect(piece, scene_.elements[element].rect);
    if (p.size() < 3) return;
    fan_.clear();
    for (std::uint32_t k = 1; k + 1 < p.size(); ++k)
        if (orient(p[0], p[k], p[k + 1]) != 0) fan_.insert(fan_.end(), {0, k, k + 1});
    if (!fan_.empty()) add_polygon(d, element, p, fan_, z);
}

// Below a scale of 1/8 a fixed margin in texels shrinks under the
// snapping error on screen: the margin grows there so that it stays
// 1/256 pixel along the element's most shrunk direction (its smallest
// singular value), up to half a texel, where a skirt or a pulled-in edge
// would reach the next texel edge.
double MeshBuilder::element_texel_margin(std::uint32_t element) const {
    const double m = texel_margin_;
    if (!(m > 0) || !std::isfinite(m)) return m;
    const auto& t = scene_.elements[element].transform;
    const double sum = t[0] * t[0] + t[1] * t[1] + t[2] * t[2] + t[3] * t[3], det = t[0] * t[3] - t[1] * t[2];
    const double smallest = std::sqrt(std::max(0.0, (sum - std::sqrt(std::max(0.0, sum * sum - 4 * det * det))) / 2));
    if (!(smallest > 0) || !std::isfinite(smallest)) return m;
    return std::max(m, std::min(0.5, (1.0 / 256) / smallest));
}

void MeshBuilder::add_texel_skirts(Draw& d, std::uint32_t element, const std::vector<Polygon>& polygons, float z,
                                   const std::vector<std::uint8_t>* skirted) {
    const double m = element_texel_margin(element);
    if (!(m > 0) || !std::isfinite(m) || (!always_skirt_ && snaps_exactly(scene_.elements[element].transform))) return;
    // Polygons (or parts of one) closer than the skirt reaches would get
    // each other's skirt over their inside texels, blending those twice:
    // no skirt for them.
    dilated_.assign(polygons.size(), 0);
    std::vector<std::uint8_t> grow(polygons.size(), 1);
    for (std::size_t a = 0; a < polygons.size(); ++a) {
        if (polygons[a].size() < 3 || !(signed_area(polygons[a]) > 0)) grow[a] = 0;
        for (std::size_t b = a; b < polygons.size(); ++b) {
            const bool same = a == b;
            if (vertex_edge_distance(polygons[a], polygons[b], same) < 3 * m ||
                (!same && vertex_edge_distance(polygons[b], polygons[a], false) < 3 * m))
                grow[a] = grow[b] = 0;
        }
    }
    for (std::size_t k = 0; k < polygons.size(); ++k) {
        if (!grow[k] || (skirted && k < skirted->size() && (*skirted)[k])) continue;
        const Polygon& p = polygons[k];
        const std::size_t n = p.size();
        std::vector<Vec2> normal(n);
        for (std::size_t i = 0; i < n; ++i) normal[i] = outward_normal(p, i);
        // Reflex corners: the two edges' strips end on the corner's exterior
        // bisector (the offset lines' crossing), so neither reaches into the
        // polygon. At a sharp corner that crossing runs far out (past the
        // 3 * m kept clear of other edges): the strips end 2 * m out on the
        // bisector instead, narrower near the corner but still outside the
        // polygon. Dropping the whole skirt there (as before) let GL's
        // snapping miss pixel centres just inside every other edge (issue
        // 21: a "moons" sprite with a notch). A crack (the edges nearly
        // folded onto each other): no skirt.
        std::vector<Vec2> offset(n);
        std::vector<std::uint8_t> reflex(n, 0), narrow(n, 0);
        bool sharp = false;
        for (std::size_t i = 0; i < n; ++i) {
            const Vec2 n1 = normal[(i + n - 1) % n], n2 = normal[i];
            const double turn = cross(n1, n2), dot = n1.x * n2.x + n1.y * n2.y;
            if (!(turn < 0)) continue; // clockwise polygon: normals turn clockwise at convex corners
            reflex[i] = 1;
            if (!(dot < -0.8)) {
                offset[i] = (m / (1 + dot)) * (n1 + n2);
                continue;
            }
            const Vec2 bisector = n1 + n2;
            const double len = std::hypot(bisector.x, bisector.y);
            if (!(len > 1e-3)) {
                sharp = true;
                continue;
            }
            offset[i] = (2 * m / len) * bisector;
            narrow[i] = 1;
        }
        // Each strip must stay on the outer side of the neighbouring edge's
        // line at a sharp corner (a short neighbour may not shield it).
        for (std::size_t i = 0; i < n && !sharp; ++i) {
            const std::size_t j = (i + 1) % n;
            const Vec2 nm = normal[i];
            if (nm.x == 0 && nm.y == 0) continue;
            const Vec2 da = reflex[i] ? offset[i] : m * nm, db = reflex[j] ? offset[j] : m * nm;
            auto outside = [&](Vec2 q, std::size_t edge) {
                const Vec2 ne = normal[edge];
                return (q.x - p[edge].x) * ne.x + (q.y - p[edge].y) * ne.y >= 0;
            };
            const std::size_t before = (i + n - 1) % n;
            if (narrow[j] && !outside(p[i] + da, j)) sharp = true;
            if (narrow[i] && !outside(p[j] + db, before)) sharp = true;
        }
        if (sharp) continue;
        if (joined_) {
            const int joined = add_joined_skirt(d, element, p, normal, offset, reflex, m, z);
            if (joined == 2) dilated_[k] = 1;
            if (joined) continue;
        }
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t j = (i + 1) % n;
            const Vec2 nm = normal[i];
            if (nm.x == 0 && nm.y == 0) continue;
            const Vec2 da = reflex[i] ? offset[i] : m * nm, db = reflex[j] ? offset[j] : m * nm;
            add_convex_piece(d, element, {p[i], p[j], p[j] + db, p[i] + da}, z);
        }
        // Convex corners: a fan from one edge's normal to the next's, in
        // steps of at most 45 degrees at radius margin / cos(step / 2),
        // covers every point within the margin of the corner.
        for (std::size_t i = 0; i < n; ++i) {
            const Vec2 n1 = normal[(i + n - 1) % n], n2 = normal[i];
            if ((n1.x == 0 && n1.y == 0) || (n2.x == 0 && n2.y == 0)) continue;
            const double turn = std::atan2(cross(n1, n2), n1.x * n2.x + n1.y * n2.y);
            if (!(turn > 0)) continue;
            const int steps = std::max(1, int(std::ceil(turn / (3.14159265358979323846 / 4))));
            const double step = turn / steps, radius = m / std::cos(step / 2), base = std::atan2(n1.y, n1.x);
            Polygon fan{p[i]};
            for (int s = 0; s <= steps; ++s)
                fan.push_back(p[i] + radius * Vec2{std::cos(base + step * s), std::sin(base + step * s)});
            add_convex_piece(d, element, fan, z);
        }
    }
}

// The joined form of one polygon's skirt (MeshBuilder::capture's
// `joined`, for the templates a FrameAssembler transforms per sprite): the
// strips end where their offset lines meet, also at convex corners, so
// neighbouring pieces share their outer vertices and a template welds them
// (a skirt vertex per corner instead of four per edge and a fan per
// corner). A convex corner turning by t gets k = ceil(t / 90 degrees)
// outer vertices on the polygon circumscribing the margin's arc there
// (radius m / cos(t / 2k) <= m * sqrt(2), within the 3 * m kept clear of
// other edges): the strips reach its first and last vertex along their
// offset lines, so the pieces still cover every point within m of the
// polygon outside it, as the fans do. Reflex corners are as above.
// A convex polygon (no reflex corner) and its skirt together are its
// outer vertices' polygon clipped to the rect, convex too: that one piece
// is added instead (returns 2; the caller leaves the polygon itself out).
// Its fan covers each point inside the polygon once, as the polygon's own
// triangles do, and the rest of it is the skirt, over transparent texels.
// Returns 0 (nothing added) for a polygon with a zero-length edge, which
// the plain form handles, else 1.
int MeshBuilder::add_joined_skirt(Draw& d, std::uint32_t element, const Polygon& p, const std::vector<Vec2>& normal,
                                   const std::vector<Vec2>& offset, const std::vector<std::uint8_t>& reflex, double m, float z) {
    const std::size_t n = p.size();
    for (const Vec2& nm : normal)
        if (nm.x == 0 && nm.y == 0) return 0;
    // Corner i's outer vertices: outer[first[i] .. first[i + 1]).
    std::vector<Vec2> outer;
    std::vector<std::size_t> first(n + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        first[i] = outer.size();
        const Vec2 n1 = normal[(i + n - 1) % n], n2 = normal[i];
        const double turn = std::atan2(cross(n1, n2), n1.x * n2.x + n1.y * n2.y);
        if (reflex[i]) {
            outer.push_back(p[i] + offset[i]);
        } else if (turn > 0) {
            const int steps = std::max(1, int(std::ceil(turn / (3.14159265358979323846 / 2))));
            const double step = turn / steps, radius = m / std::cos(step / 2), base = std::atan2(n1.y, n1.x);
            for (int s = 0; s < steps; ++s)
                outer.push_back(p[i] + radius * Vec2{std::cos(base + step * (s + 0.5)), std::sin(base + step * (s + 0.5))});
        } else {
            outer.push_back(p[i] + m * n2); // straight on: both strips end on the shared normal
        }
    }
    first[n] = outer.size();
    if (std::find(reflex.begin(), reflex.end(), std::uint8_t(1)) == reflex.end() && is_convex(p)) {
        add_convex_piece(d, element, outer, z);
        return 2;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        add_convex_piece(d, element, {p[i], p[j], outer[first[j]], outer[first[i + 1] - 1]}, z);
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (first[i + 1] - first[i] < 2) continue;
        Polygon fan{p[i]};
        fan.insert(fan.end(), outer.begin() + std::ptrdiff_t(first[i]), outer.begin() + std::ptrdiff_t(first[i + 1]));
        add_convex_piece(d, element, fan, z);
    }
    return 1;
}

Polygon move_edges_inward(const Polygon& p, const std::vector<double>& d) {
    const std::size_t n = p.size();
    if (n < 3 || d.size() != n) return {};
    const double sign = signed_area(p) > 0 ? 1.0 : -1.0;
    std::vector<Vec2> inward(n); // unit normals
    for (std::size_t k = 0; k < n; ++k) {
        const Vec2 e = p[(k + 1) % n] - p[k];
        const double len = std::hypot(e.x, e.y);
        if (!(len > 0)) return {};
        // Positive signed area is clockwise with y down: the inside is to the right of an edge.
        inward[k] = {-sign * e.y / len, sign * e.x / len};
    }
    Polygon out;
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k0 = (i + n - 1) % n, k1 = i;
        const Vec2 a = inward[k0], b = inward[k1];
        const double det = a.x * b.y - a.y * b.x;
        if (std::abs(det) > 1e-12) {
            // p[i] + v on both moved lines: v . a = d[k0], v . b = d[k1].
            out.push_back(p[i] + Vec2{(d[k0] * b.y - d[k1] * a.y) / det, (a.x * d[k1] - b.x * d[k0]) / det});
        } else if (a.x * b.x + a.y * b.y > 0 && d[k0] == d[k1]) {
            out.push_back(p[i] + d[k0] * a); // collinear neighbours
        } else {
            return {};
        }
    }
    // Too small (an edge would flip or the polygon turn over): none.
    Polygon positive = out;
    if (sign < 0) std::reverse(positive.begin(), positive.end());
    if (!is_convex(positive)) return {};
    for (std::size_t k = 0; k < n; ++k) {
        const Vec2 e = p[(k + 1) % n] - p[k], f = out[(k + 1) % n] - out[k];
        if (!(e.x * f.x + e.y * f.y > 0)) return {};
    }
    return out;
}

std::vector<double> side_margins(const Scene& scene, const Element& e, const Polygon& texel, double margin) {
    std::vector<double> d(texel.size(), margin);
    if (scene.filter != Filter::nearest || !pixel_aligned(scene, e)) return d;
    const double x0 = e.rect.x, x1 = double(e.rect.x) + e.rect.w, y0 = e.rect.y, y1 = double(e.rect.y) + e.rect.h;
    for (std::size_t k = 0; k < texel.size(); ++k) {
        const Vec2 u = texel[k], v = texel[(k + 1) % texel.size()];
        if ((u.x == v.x && (u.x == x0 || u.x == x1)) || (u.y == v.y && (u.y == y0 || u.y == y1))) d[k] = 0;
    }
    return d;
}

Polygon MeshBuilder::pull_inward(std::uint32_t element, const Polygon& analysis_polygon) const {
    const Element& e = scene_.elements[element];
    const Polygon p = capture_ ? analysis_polygon : opaque_to_rect_sides(scene_, e, analysis_polygon);
    const double m = element_texel_margin(element);
    if (!(m > 0) || p.size() < 3) return p;
    // Each edge's line moved m inward (consecutive lines meet at the new
    // corner), but for edges on the sides of a pixel-aligned rect: those lie
    // on whole pixels, where GL has no snapping error to leave room for, and
    // there the polygon must meet what the rect drew (side_margins).
    // (A captured template is never moved out, so none of its edges is on a side.)
    return move_edges_inward(p, side_margins(scene_, e, p, m));
}

} // namespace depthcull::detail
