// Dynamic elements (beyond the paper: section 4, caveat 2, notes that a
// changing scene must be reconstructed). Moving elements drawn on top of a
// static scene need no graph: levels above every static level, one per
// element in drawing order, keep each in front of everything drawn before
// it. The static scene reserves those levels (reserved_dynamic_levels) so
// its depth mapping already leaves room; nothing static is recomputed.
#include <algorithm>
#include <cstdint>

#include "scene/internal.h"

namespace depthcull {

using namespace detail;

ReconstructStatus add_dynamic_elements(const SceneMeshes& static_meshes, const Scene& scene,
                                       const std::vector<Element>& elements,
                                       const std::vector<const ImageAnalysis*>& analyses, SceneMeshes* frame,
                                       bool element_spans) {
    const std::int64_t denominator = static_meshes.depth_denominator;
    if (!frame || analyses.size() != elements.size() || denominator < 2 || static_meshes.stats.elements < 0 ||
        static_meshes.stats.elements > std::int64_t(UINT32_MAX) - std::int64_t(elements.size()))
        return ReconstructStatus::invalid_scene;
    // From the draws, not stats.depth_levels: a stated value that is too
    // large overflowed to level 0 and one too small put the elements
    // behind the static ones (issue 21).
    const std::int64_t first_level = depth_levels_of_draws(static_meshes.draws, denominator);
    // Levels k with (2k+2)/D <= 1 are usable.
    if (first_level + std::int64_t(elements.size()) > denominator / 2 - 1) return ReconstructStatus::too_many_depth_levels;

    Scene dynamic;
    dynamic.viewport = scene.viewport;
    dynamic.filter = scene.filter;
    dynamic.images = scene.images;
    dynamic.elements = elements;
    for (std::size_t i = 0; i < elements.size(); ++i) {
        const Element& e = elements[i];
        if (!element_is_valid(dynamic, e)) return ReconstructStatus::invalid_scene;
        if (!analyses[i] && e.blend != Blend::opaque && e.blend != Blend::multiply) return ReconstructStatus::invalid_scene;
    }
    ElementShapes shapes = element_shapes(dynamic, analyses, static_meshes.depth_test, true); // kTexelMargin, no coverage skirts
    std::vector<std::int32_t> keys = mesh_keys(dynamic);
    std::vector<std::int64_t> levels(elements.size());
    std::vector<std::uint32_t> order;
    for (std::size_t i = 0; i < elements.size(); ++i) {
        levels[i] = first_level + std::int64_t(i);
        if (shapes.blended[i]) order.push_back(std::uint32_t(i));
    }

    SceneMeshes out;
    out.viewport = static_meshes.viewport;
    out.depth_test = static_meshes.depth_test;
    out.filter = static_meshes.filter;
    out.depth_denominator = denominator;
    // Dynamic elements follow the static ones in element spans, so the
    // static draws' spans stay valid as they are.
    const auto first_element = std::uint32_t(static_meshes.stats.elements);
    MeshBuilder builder(dynamic, first_element, 0, kTexelMargin, element_spans);
    std::vector<std::uint32_t> all(elements.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = std::uint32_t(i);
    // Dynamic opaque draws first: they are nearest, so they reject the most.
    append_opaque_draws(dynamic, all, levels, shapes, analyses, keys, denominator, builder, out.draws);
    const std::vector<int> canon = canonical_images(dynamic);
    std::int32_t last = -1;
    bool first_blend = true;
    for (std::uint32_t e : order) {
        const Element& el = elements[e];
        if (first_blend || keys[e] != last) {
            Draw d;
            d.image = canon[std::size_t(el.image)];
            d.pass = Pass::blend;
            d.blend = el.blend;
            out.draws.push_back(std::move(d));
            last = keys[e];
            first_blend = false;
        }
        builder.add_boundary(out.draws.back(), e, shapes.boundary[e], analyses[e], depth_z(levels[e], false, denominator));
    }
    out.stats = static_meshes.stats;
    out.stats.elements += std::int64_t(elements.size());
    std::int64_t used = 0;
    for (std::size_t i = 0; i < elements.size(); ++i)
        if (shapes.boundary[i] != Shape::none) used = std::int64_t(i) + 1;
    out.stats.depth_levels = first_level + used;
    finish_stats(out);
    *frame = std::move(out);
    return ReconstructStatus::ok;
}

SceneMeshes compose_frame(const SceneMeshes& static_meshes, const SceneMeshes& dynamic) {
    SceneMeshes frame = dynamic;
    auto blend = std::find_if(frame.draws.begin(), frame.draws.end(), [](const Draw& d) { return d.pass != Pass::opaque; });
    frame.draws.insert(blend, static_meshes.draws.begin(), static_meshes.draws.end());
    finish_stats(frame);
    return frame;
}

} // namespace depthcull
