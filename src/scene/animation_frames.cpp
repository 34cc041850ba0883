// Animations (Element::animation). One analysis for an animation's frames (Element::animation): the image it
// runs on and how its polygons land on frame 0's rect. Shared by the
// pipeline (through the cache) and the wasm reconstruction (no cache), so
// both give the same polygons.
#include "depthcull/scene.h"

namespace depthcull {

Image animation_alpha(const std::vector<ImageView>& images, const Animation& animation) {
    const AnimationFrame& first = animation.frames.front();
    const int w = first.rect.w, h = first.rect.h;
    Image combined;
    combined.width = w;
    combined.height = h;
    combined.rgba.assign(std::size_t(w) * std::size_t(h) * 4, 0);
    std::vector<std::uint8_t> any(std::size_t(w) * std::size_t(h), 0), all(std::size_t(w) * std::size_t(h), 1);
    for (const AnimationFrame& f : animation.frames) {
        const ImageView& view = images[std::size_t(f.image)];
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const std::uint8_t a = view.alpha(f.rect.x + x, f.rect.y + y);
                const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
                any[i] |= a != 0;
                all[i] &= a == 255;
            }
    }
    for (std::size_t i = 0; i < any.size(); ++i) combined.rgba[4 * i + 3] = all[i] ? 255 : any[i] ? 128 : 0;
    return combined;
}

void place_animation_analysis(ImageAnalysis& a, const std::vector<ImageView>& images, const Animation& animation) {
    const AnimationFrame& first = animation.frames.front();
    const double dx = first.rect.x, dy = first.rect.y;
    for (auto* polygons : {&a.boundary, &a.opaque})
        for (Polygon& p : *polygons)
            for (Vec2& v : p) v = {v.x + dx, v.y + dy};
    a.rect = first.rect;
    // The combined image has no neighbours: ask each frame's page.
    a.bleeding_edges = false;
    for (const AnimationFrame& f : animation.frames) a.bleeding_edges |= edges_bleed(images[std::size_t(f.image)], f.rect);
}

std::vector<AnimatedRun> animated_runs(const Scene& scene, const SceneMeshes& meshes) {
    std::vector<AnimatedRun> runs;
    if (scene.animations.empty()) return runs;
    for (std::size_t d = 0; d < meshes.draws.size(); ++d) {
        const Draw& draw = meshes.draws[d];
        const std::vector<ElementSpan>& spans = draw.element_spans;
        for (std::size_t j = 0; j < spans.size();) {
            std::size_t next = j + 1;
            while (next < spans.size() && spans[next].element == spans[j].element) ++next;
            const std::size_t first = spans[j].first_vertex, end = next < spans.size() ? spans[next].first_vertex : draw.vertex_count();
            const std::uint32_t element = spans[j].element;
            const int animation = element < scene.elements.size() ? scene.elements[element].animation : -1;
            if (animation >= 0 && end > first)
                runs.push_back({std::uint32_t(d), std::uint32_t(first), std::uint32_t(end - first), std::uint32_t(animation)});
            j = next;
        }
    }
    return runs;
}

} // namespace depthcull
