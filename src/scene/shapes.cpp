// What each element draws. The rules keep every element looking exactly
// as overpaint draws it (its whole rect, blended):
// - alpha / add: the boundary polygons; outside them every texel is
//   transparent, which these blend modes leave unchanged (paper 2.1).
// - multiply: the whole rect. Whether a transparent texel leaves the pixel
//   unchanged depends on the renderer's multiply equation, so we do not
//   rely on it; multiply sprites are rare and gain little.
// - opaque: texel alpha is ignored, so the whole rect is both the boundary
//   and the opaque polygon.
// - a boundary that leaves the rect (e.g. grown half a texel for linear
//   filtering at the rect's edge) would draw pixels overpaint never
//   touches, so such an element falls back to its rect.
// - colour alpha 0 with alpha / add changes nothing: dropped.
// Opaque polygons (paper 2.2) only where the opaque pass writes exactly
// what blending would: blend alpha with colour alpha 1. Elements whose
// opaque polygons cover all they draw skip the blend pass (see below).
#include <algorithm>
#include <cmath>
#include <map>

#include "scene/internal.h"
#include "scene/placement.h"

namespace depthcull::detail {

bool element_is_valid(const Scene& scene, const Element& e) {
    if (e.image < 0 || std::size_t(e.image) >= scene.images.size() || e.rect.empty()) return false;
    for (double v : e.transform)
        if (!std::isfinite(v)) return false;
    for (float c : e.color)
        if (!std::isfinite(c)) return false;
    return true;
}

Polygon rect_polygon(const Rect& r) {
    double x0 = r.x, y0 = r.y, x1 = double(r.x) + r.w, y1 = double(r.y) + r.h;
    return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
}

// True when the element's rect lands on whole screen pixels along the
// axes (flips and quarter turns allowed): then no pixel centre lies on the
// rect's edge, so every pixel the rect covers samples a texel inside it.
bool pixel_aligned(const Scene& scene, const Element& e) {
    auto is_integer = [](double v) { return std::floor(v) == v; };
    const auto& m = e.transform;
    bool axis_aligned = (m[1] == 0 && m[2] == 0) || (m[0] == 0 && m[3] == 0);
    if (!axis_aligned || !is_integer(scene.viewport.x) || !is_integer(scene.viewport.y)) return false;
    for (Vec2 c : {Vec2{0, 0}, Vec2{double(e.rect.w), double(e.rect.h)}}) {
        Vec2 p = apply(m, c);
        if (!is_integer(p.x) || !is_integer(p.y)) return false;
    }
    return true;
}

// The analysis keeps opaque polygons half a texel inside the rect: its
// guarantee (docs/opaque.md) counts texels outside the rect as non-opaque
// and lets no edge run along a non-opaque texel's side, as a pixel centre
// on such an edge could sample it. A pixel-aligned element has no pixel
// centre on its rect's sides, and with nearest filtering a centre in the
// strip between an edge on x = rect.x + 0.5 (from y0 to y1) and the side
// x = rect.x samples a texel of column rect.x in rows y0..y1, each of which
// the polygon's interior already meets just inside that edge: opaque by
// the guarantee. So the edge may move out onto the side. Only an edge whose
// neighbours run at right angles to it moves, so that the polygon grows by
// that strip alone and stays convex; the sides are taken in turn, so a
// corner of two moved edges moves out to the rect's corner (its texel is
// met by the interior too). Elements behind then lose their thin rims of
// pixels under an element in front instead of drawing (or being cut into)
// them.
Polygon opaque_to_rect_sides(const Scene& scene, const Element& e, const Polygon& p) {
    const std::size_t n = p.size();
    if (n < 4 || scene.filter != Filter::nearest || e.rect.w < 2 || e.rect.h < 2 || !pixel_aligned(scene, e)) return p;
    Polygon q = p;
    const double x0 = e.rect.x, x1 = double(e.rect.x) + e.rect.w, y0 = e.rect.y, y1 = double(e.rect.y) + e.rect.h;
    struct Side {
        bool vertical; // the edge runs along y (a left or right side)
        double line, side;
    };
    for (const Side& s : {Side{true, x0 + 0.5, x0}, Side{true, x1 - 0.5, x1}, Side{false, y0 + 0.5, y0}, Side{false, y1 - 0.5, y1}}) {
        // The polygon must lie on the inner side of the line (it is convex).
        bool inner = true;
        for (const Vec2& v : q) inner = inner && (s.side < s.line ? (s.vertical ? v.x : v.y) >= s.line : (s.vertical ? v.x : v.y) <= s.line);
        if (!inner) continue;
        for (std::size_t i = 0; i < n; ++i) {
            Vec2 &a = q[i], &b = q[(i + 1) % n];
            const Vec2 before = q[(i + n - 1) % n], after = q[(i + 2) % n];
            const bool on = s.vertical ? a.x == s.line && b.x == s.line && a.y != b.y : a.y == s.line && b.y == s.line && a.x != b.x;
            if (!on) continue;
            // The neighbours at right angles: the polygon grows by the strip alone.
            const bool square = s.vertical ? before.y == a.y && before.x != a.x && after.y == b.y && after.x != b.x
                                           : before.x == a.x && before.y != a.y && after.x == b.x && after.y != b.y;
            if (square) {
                if (s.vertical) a.x = b.x = s.side;
                else a.y = b.y = s.side;
            }
            break; // a convex polygon has one edge on a line at most
        }
    }
    return q;
}

namespace {

bool inside_rect(const std::vector<Polygon>& polygons, const Rect& r) {
    for (const Polygon& p : polygons)
        for (const Vec2& v : p)
            if (v.x < r.x || v.y < r.y || v.x > double(r.x) + r.w || v.y > double(r.y) + r.h) return false;
    return true;
}

// A wholly opaque rect (every texel alpha 255: tiles, backgrounds) whose
// element is pixel-aligned can be its own opaque polygon. The analysis
// keeps opaque polygons half a texel inside the rect, because it cannot
// know how the rect will be placed; here we do know, and the rect drawn
// with blending off writes exactly what overpaint's blended rect writes.
bool whole_rect_opaque(const Scene& scene, const Element& e, const ImageAnalysis* a) {
    return a && a->stats.opaque_texels == std::int64_t(e.rect.w) * e.rect.h && pixel_aligned(scene, e);
}

Shape boundary_shape(const Scene& scene, const Element& e, const ImageAnalysis* a) {
    if (!element_is_valid(scene, e)) return Shape::none;
    if (e.blend == Blend::opaque || e.blend == Blend::multiply) return Shape::rect;
    if (e.color[3] <= 0.0f) return Shape::none;
    if (!a || a->boundary.empty()) return Shape::none;
    return inside_rect(a->boundary, e.rect) ? Shape::analysis : Shape::rect;
}

} // namespace

// In a plain renderer (texel_margin.cpp) GL snaps the corners of
// overpaint's quad, and a pixel centre within the snapping error of the
// rect's edge may fall on either side of it: inside, overpaint shows the
// rect's border texel; just outside, it shows the texel past the edge (the
// next frame of an atlas page; past the image, clamping shows the border
// texel again). The optimized meshes draw such a pixel alike only with an
// edge snapped from the same two corners: a polygon edge along part of the
// rect's edge snaps from other vertices, and the texel skirt stops at the
// rect (it must: past it lie texels the analysis never saw). So an element
// whose vertices GL snaps draws its whole rect in the blend pass, from
// overpaint's own corners, when one of those texels is non-transparent
// (ImageAnalysis::bleeding_edges). Tiles (snaps_exactly) and sprites with
// a transparent border and ring keep their polygons. FrameAssembler
// applies the same rule per sprite per frame (frame_assembler.cpp).
bool needs_rect_edges(bool bleeding_edges, const std::array<double, 6>& transform) {
    return bleeding_edges && !snaps_exactly(transform);
}

ElementShapes element_shapes(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses, bool opaque_pass,
                             bool rect_edges) {
    const std::size_t n = scene.elements.size();
    ElementShapes s;
    s.boundary.resize(n, Shape::none);
    s.opaque.resize(n, Shape::none);
    s.blended.resize(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const Element& e = scene.elements[i];
        const ImageAnalysis* a = i < analyses.size() ? analyses[i] : nullptr;
        s.boundary[i] = boundary_shape(scene, e, a);
        if (s.boundary[i] == Shape::none) continue;
        if (rect_edges && s.boundary[i] == Shape::analysis && needs_rect_edges(a->bleeding_edges, e.transform)) s.boundary[i] = Shape::rect;
        if (opaque_pass) {
            if (e.blend == Blend::opaque) s.opaque[i] = Shape::rect;
            else if (e.blend == Blend::alpha && e.color[3] == 1.0f && whole_rect_opaque(scene, e, a)) {
                s.opaque[i] = Shape::rect;
                s.blended[i] = 0; // the opaque rect draws all of it
                continue;
            } else if (e.blend == Blend::alpha && e.color[3] == 1.0f && a && !a->opaque.empty())
                s.opaque[i] = Shape::analysis;
        }
        s.blended[i] = !(opaque_pass && e.blend == Blend::opaque);
        // Beyond the paper: when the opaque polygons cover every
        // non-transparent texel (all of them opaque), the blend pass could
        // only draw transparent texels or fragments the element's own opaque
        // polygons reject, so the element needs no blend draw. Only with
        // nearest sampling: bilinear filtering blends the texels around the
        // opaque polygons' edges into partly transparent fragments.
        if (s.opaque[i] == Shape::analysis && scene.filter == Filter::nearest && a->stats.nontransparent_texels > 0 &&
            a->stats.opaque_covered_texels == a->stats.nontransparent_texels && s.boundary[i] == Shape::analysis)
            s.blended[i] = 0;
    }
    return s;
}

void cull_to_viewport(const Scene& scene, ElementShapes& shapes) {
    const Viewport& vp = scene.viewport;
    if (vp.width <= 0 || vp.height <= 0) return;
    const double x0 = vp.x - 1, y0 = vp.y - 1, x1 = vp.x + vp.width + 1, y1 = vp.y + vp.height + 1;
    for (std::size_t i = 0; i < scene.elements.size(); ++i) {
        if (shapes.boundary[i] == Shape::none) continue;
        const Element& e = scene.elements[i];
        double bx0 = INFINITY, by0 = INFINITY, bx1 = -INFINITY, by1 = -INFINITY;
        for (Vec2 c : {Vec2{0, 0}, Vec2{double(e.rect.w), 0}, Vec2{0, double(e.rect.h)}, Vec2{double(e.rect.w), double(e.rect.h)}}) {
            Vec2 s = apply(e.transform, c);
            bx0 = std::min(bx0, s.x), by0 = std::min(by0, s.y), bx1 = std::max(bx1, s.x), by1 = std::max(by1, s.y);
        }
        if (bx1 < x0 || bx0 > x1 || by1 < y0 || by0 > y1) {
            shapes.boundary[i] = Shape::none;
            shapes.opaque[i] = Shape::none;
            shapes.blended[i] = 0;
        }
    }
}

std::vector<int> canonical_images(const Scene& scene) {
    std::vector<int> canon(scene.images.size());
    std::map<std::string, int> first;
    for (std::size_t i = 0; i < scene.images.size(); ++i)
        canon[i] = first.emplace(scene.images[i].path, int(i)).first->second;
    return canon;
}

std::vector<std::int32_t> mesh_keys(const Scene& scene) {
    std::vector<int> canon = canonical_images(scene);
    std::vector<std::int32_t> keys(scene.elements.size(), -1);
    for (std::size_t i = 0; i < keys.size(); ++i) {
        const Element& e = scene.elements[i];
        if (e.image < 0 || std::size_t(e.image) >= canon.size()) continue;
        keys[i] = std::int32_t(canon[std::size_t(e.image)] * 4 + int(e.blend));
    }
    return keys;
}

} // namespace depthcull::detail

namespace depthcull {

bool can_share_mesh(const Scene& scene, const Element& a, const Element& b) {
    auto valid = [&](const Element& e) { return e.image >= 0 && std::size_t(e.image) < scene.images.size(); };
    if (!valid(a) || !valid(b) || a.blend != b.blend) return false;
    return a.image == b.image || scene.images[std::size_t(a.image)].path == scene.images[std::size_t(b.image)].path;
}

} // namespace depthcull
