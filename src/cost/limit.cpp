// Issue 25 point 1: the limit, the cost model's frame time of the ideal
// frame (limit_features in depthcull/cost.h).
#include <algorithm>
#include <cmath>
#include <set>

#include "depthcull/cost.h"
#include "depthcull/overdraw.h"

namespace depthcull {

namespace {

// Sutherland-Hodgman against one axis-aligned half plane (coord >= bound
// for sign 1, <= for -1; axis 0: x, 1: y).
Polygon clip_half(const Polygon& in, int axis, double bound, double sign) {
    Polygon out;
    for (std::size_t i = 0; i < in.size(); ++i) {
        const Vec2 a = in[i], b = in[(i + 1) % in.size()];
        const double ca = axis == 0 ? a.x : a.y, cb = axis == 0 ? b.x : b.y;
        const bool ia = sign * (ca - bound) >= 0, ib = sign * (cb - bound) >= 0;
        if (ia) out.push_back(a);
        if (ia != ib) out.push_back(a + ((bound - ca) / (cb - ca)) * (b - a));
    }
    return out;
}

} // namespace

FrameFeatures limit_features(const Scene& scene, const std::vector<ImageView>& images) {
    FrameFeatures f;
    const Viewport& vp = scene.viewport;
    std::vector<std::uint8_t> shows;
    const OverdrawStats ideal = ideal_overdraw(scene, images, nullptr, &shows);
    f.pixels = ideal.pixels;
    f.blend_fragments = ideal.shaded;
    f.opaque_blocks = ideal.blocks_opaque;
    f.blend_blocks = ideal.blocks_blend;
    std::set<std::string> textures;
    for (std::size_t i = 0; i < scene.elements.size(); ++i) {
        if (!shows[i]) continue;
        const Element& e = scene.elements[i];
        const SceneImage& img = scene.images[std::size_t(e.image)];
        textures.insert(img.path.empty() ? "#" + img.id : img.path);
        f.triangles += 2;
        Polygon p;
        for (Vec2 c : {Vec2{0, 0}, Vec2{double(e.rect.w), 0}, Vec2{double(e.rect.w), double(e.rect.h)}, Vec2{0, double(e.rect.h)}})
            p.push_back(apply(e.transform, c));
        p = clip_half(p, 0, vp.x, 1);
        if (!p.empty()) p = clip_half(p, 0, vp.x + vp.width, -1);
        if (!p.empty()) p = clip_half(p, 1, vp.y, 1);
        if (!p.empty()) p = clip_half(p, 1, vp.y + vp.height, -1);
        if (p.size() < 3) continue;
        // Two triangles: the outline and a diagonal twice (as a fan of the
        // clipped polygon would have more, this is the least).
        double outline = 0;
        for (std::size_t k = 0; k < p.size(); ++k) outline += std::hypot(p[(k + 1) % p.size()].x - p[k].x, p[(k + 1) % p.size()].y - p[k].y);
        double diagonal = INFINITY;
        for (std::size_t k = 0; k < p.size(); ++k)
            for (std::size_t j = k + 2; j < p.size(); ++j)
                if (!(k == 0 && j + 1 == p.size())) diagonal = std::min(diagonal, std::hypot(p[j].x - p[k].x, p[j].y - p[k].y));
        f.triangle_perimeter += outline + (std::isfinite(diagonal) ? 2 * diagonal : 0);
    }
    f.draw_calls = f.texture_switches = std::int64_t(textures.size());
    return f;
}

} // namespace depthcull
