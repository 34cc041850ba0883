// The unoptimized method the paper measures against (Table 2,
// "Unoptimized"): every element's whole rect, one draw each, back to front.
// With a coverage margin (for frame comparisons, see scene.h) each rect but
// a Blend::opaque one gets the same skirt a reconstructed element's
// polygons get, so GL's vertex snapping decides no pixel in either.
#include "scene/internal.h"

namespace depthcull {

SceneMeshes overpaint_meshes(const Scene& scene, double coverage_margin, bool element_spans) {
    detail::MeshBuilder skirts(scene, 0, coverage_margin, kTexelMargin, element_spans);
    SceneMeshes out;
    out.viewport = scene.viewport;
    out.depth_test = false;
    out.filter = scene.filter;
    out.draws.reserve(scene.elements.size());
    for (const Element& e : scene.elements) {
        const SceneImage& img = scene.images[std::size_t(e.image)];
        Draw d;
        d.image = e.image;
        d.pass = Pass::blend;
        d.blend = e.blend;
        const Vec2 corners[4] = {{0, 0}, {double(e.rect.w), 0}, {double(e.rect.w), double(e.rect.h)}, {0, double(e.rect.h)}};
        for (const Vec2& c : corners) {
            Vec2 s = apply(e.transform, c);
            d.vertices.insert(d.vertices.end(),
                              {float(s.x), float(s.y), 0.0f, float((e.rect.x + c.x) / img.width),
                               float((e.rect.y + c.y) / img.height), e.color[0], e.color[1], e.color[2], e.color[3]});
        }
        d.indices = {0, 1, 2, 0, 2, 3};
        if (element_spans) d.element_spans.push_back({std::uint32_t(out.draws.size()), 0});
        if (coverage_margin > 0 && e.blend != Blend::opaque)
            skirts.add_skirts(d, std::uint32_t(out.draws.size()), {detail::rect_polygon(e.rect)}, 0.0f);
        out.draws.push_back(std::move(d));
    }
    out.stats.elements = std::int64_t(scene.elements.size());
    detail::finish_stats(out);
    out.stats.depth_levels = 0;
    return out;
}

} // namespace depthcull
