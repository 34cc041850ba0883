// depthcull.h: scenes, reconstruction (paper 2.3) and dynamic elements.
#include <cmath>
#include <limits>
#include <map>

#include "capi/capi_internal.h"
#include "depthcull/pipeline.h"

using namespace depthcull;
using depthcull::capi::fail;
using depthcull::capi::guard;

namespace {

// Far beyond any screen, and keeps every product finite (as the scene JSON).
constexpr double kMaxTransformValue = 1e9;

// Empty when `e` is a valid element of `scene` with analysis `a`, else why not.
std::string element_problem(const Scene& scene, const dc_element& e, const dc_analysis* a) {
    if (e.image >= scene.images.size()) return "image " + std::to_string(e.image) + " is not one of the scene's " + std::to_string(scene.images.size());
    const SceneImage& img = scene.images[e.image];
    const Rect r{e.rect.x, e.rect.y, e.rect.w, e.rect.h};
    if (r.empty() || !ImageView{nullptr, img.width, img.height, 0}.contains(r))
        return "rect is empty or outside the " + std::to_string(img.width) + "x" + std::to_string(img.height) + " image \"" + img.id + "\"";
    for (double t : e.transform)
        if (!(std::fabs(t) <= kMaxTransformValue)) return "transform values must be finite and within +-1e9";
    for (float c : e.color)
        if (!(c >= 0 && c <= 1)) return "color components must be in 0..1";
    if (e.blend < DC_BLEND_ALPHA || e.blend > DC_BLEND_OPAQUE) return "blend must be a dc_blend";
    if (!a && e.blend != DC_BLEND_OPAQUE && e.blend != DC_BLEND_MULTIPLY) return "an alpha or add element needs its analysis";
    if (a && !(a->analysis->rect == r)) return "the analysis is of another rect than the element's";
    return {};
}

Element to_element(const dc_element& e) {
    Element out;
    out.image = int(e.image);
    out.rect = {e.rect.x, e.rect.y, e.rect.w, e.rect.h};
    for (int k = 0; k < 6; ++k) out.transform[std::size_t(k)] = e.transform[k];
    for (int k = 0; k < 4; ++k) out.color[std::size_t(k)] = e.color[k];
    out.blend = Blend(e.blend);
    return out;
}

// The scene's per-element analyses as pipeline::optimize takes them: each
// distinct one once, elements by index (past the end: none).
SceneAnalysis scene_analysis(const std::vector<std::shared_ptr<const ImageAnalysis>>& analyses) {
    SceneAnalysis out;
    std::map<const ImageAnalysis*, std::uint32_t> index;
    out.of_element.reserve(analyses.size());
    for (const auto& a : analyses) {
        if (!a) {
            out.of_element.push_back(std::numeric_limits<std::uint32_t>::max());
            continue;
        }
        auto [it, fresh] = index.emplace(a.get(), std::uint32_t(out.images.size()));
        if (fresh) out.images.push_back(*a);
        out.of_element.push_back(it->second);
    }
    return out;
}

} // namespace

extern "C" {

void dc_element_default(dc_element* element) {
    if (!element) return;
    *element = dc_element{0, {0, 0, 0, 0}, {1, 0, 0, 1, 0, 0}, {1, 1, 1, 1}, DC_BLEND_ALPHA};
}

void dc_reconstruct_options_default(dc_reconstruct_options* options) {
    if (!options) return;
    const ReconstructOptions d;
    *options = dc_reconstruct_options{d.graph == GraphMode::boxes ? DC_GRAPH_BOXES : DC_GRAPH_POLYGONS,
                                      d.sort == SortMethod::none ? DC_SORT_NONE : d.sort == SortMethod::paper ? DC_SORT_PAPER : DC_SORT_BATCH,
                                      d.opaque_polygons, d.reserved_dynamic_levels, d.cull_to_viewport, d.texel_margin};
}

dc_status dc_scene_create(dc_viewport viewport, dc_scene** out) {
    return guard("dc_scene_create", [&] {
        if (!out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_scene_create: out must not be NULL");
        if (!std::isfinite(viewport.x) || !std::isfinite(viewport.y) || viewport.width <= 0 || viewport.height <= 0)
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_scene_create: the viewport needs a finite origin and a positive size");
        auto scene = std::make_unique<dc_scene>();
        scene->scene.viewport = {viewport.x, viewport.y, viewport.width, viewport.height};
        *out = scene.release();
        return DC_OK;
    });
}

void dc_scene_destroy(dc_scene* scene) { delete scene; }

dc_status dc_scene_add_image(dc_scene* scene, const char* id, const char* path, int width, int height, uint32_t* index) {
    return guard("dc_scene_add_image", [&] {
        if (!scene || !id) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_scene_add_image: scene and id must not be NULL");
        if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide)
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_scene_add_image: image \"" + std::string(id) + "\": size must be 1.." + std::to_string(kMaxImageSide) + " per side");
        if (scene->scene.images.size() >= io::kMaxMeshImages)
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_scene_add_image: more than " + std::to_string(io::kMaxMeshImages) + " images");
        // Ids name images in the meshes JSON, so they must tell them apart.
        for (const SceneImage& img : scene->scene.images)
            if (img.id == id) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_scene_add_image: duplicate image id \"" + std::string(id) + "\"");
        scene->scene.images.push_back(SceneImage{id, path ? path : "", width, height});
        if (index) *index = uint32_t(scene->scene.images.size() - 1);
        return DC_OK;
    });
}

dc_status dc_scene_add_element(dc_scene* scene, const dc_element* element, const dc_analysis* analysis) {
    return guard("dc_scene_add_element", [&] {
        if (!scene || !element) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_scene_add_element: scene and element must not be NULL");
        if (std::string problem = element_problem(scene->scene, *element, analysis); !problem.empty())
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_scene_add_element: element " + std::to_string(scene->scene.elements.size()) + ": " + problem);
        scene->scene.elements.push_back(to_element(*element));
        scene->analyses.push_back(analysis ? analysis->analysis : nullptr);
        return DC_OK;
    });
}

size_t dc_scene_element_count(const dc_scene* scene) { return scene ? scene->scene.elements.size() : 0; }

dc_status dc_reconstruct(const dc_scene* scene, const dc_reconstruct_options* options, dc_meshes** out) {
    return guard("dc_reconstruct", [&] {
        if (!scene || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_reconstruct: scene and out must not be NULL");
        dc_reconstruct_options o;
        dc_reconstruct_options_default(&o);
        if (options) o = *options;
        if (o.graph < DC_GRAPH_POLYGONS || o.graph > DC_GRAPH_BOXES || o.sort < DC_SORT_NONE || o.sort > DC_SORT_BATCH)
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_reconstruct: graph and sort must be a dc_graph_mode and a dc_sort_method");
        if (o.reserved_dynamic_levels < 0 || o.reserved_dynamic_levels > kMaxDepthLevels)
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_reconstruct: reserved_dynamic_levels must be 0.." + std::to_string(kMaxDepthLevels));
        if (!(o.texel_margin >= 0 && o.texel_margin <= 0.25)) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_reconstruct: texel_margin must be in 0..0.25");
        ReconstructOptions r;
        r.graph = o.graph == DC_GRAPH_BOXES ? GraphMode::boxes : GraphMode::polygons;
        r.sort = o.sort == DC_SORT_NONE ? SortMethod::none : o.sort == DC_SORT_PAPER ? SortMethod::paper : SortMethod::batch;
        r.opaque_polygons = o.opaque_polygons != 0;
        r.reserved_dynamic_levels = o.reserved_dynamic_levels;
        r.cull_to_viewport = o.cull_to_viewport != 0;
        r.texel_margin = o.texel_margin;
        r.insertion_points = scene->points;
        pipeline::OptimizeOptions optimize;
        optimize.reconstruct = r;
        pipeline::OptimizeResult result = pipeline::optimize({scene->scene, scene_analysis(scene->analyses)}, optimize);
        if (dc_status s = capi::reconstruct_status("dc_reconstruct", result.status)) return s;
        auto meshes = std::make_unique<dc_meshes>();
        meshes->document.meshes = std::move(result.meshes);
        // Timed by the pipeline, at its edge: the core's values hold no clock readings.
        meshes->seconds = result.seconds.reconstruction;
        meshes->document.images = scene->scene.images;
        *out = meshes.release();
        return DC_OK;
    });
}

dc_status dc_add_dynamic_elements(const dc_meshes* static_meshes, const dc_scene* scene, const dc_element* elements,
                                  const dc_analysis* const* analyses, size_t count, dc_meshes* frame) {
    return guard("dc_add_dynamic_elements", [&] {
        if (!static_meshes || !scene || !frame || (count && (!elements || !analyses)))
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_add_dynamic_elements: static_meshes, scene, frame, elements and analyses must not be NULL");
        std::vector<Element> dynamic(count);
        std::vector<const ImageAnalysis*> dynamic_analyses(count);
        for (std::size_t i = 0; i < count; ++i) {
            if (std::string problem = element_problem(scene->scene, elements[i], analyses[i]); !problem.empty())
                return fail(DC_ERROR_INVALID_ARGUMENT, "dc_add_dynamic_elements: element " + std::to_string(i) + ": " + problem);
            dynamic[i] = to_element(elements[i]);
            dynamic_analyses[i] = analyses[i] ? analyses[i]->analysis.get() : nullptr;
        }
        // Only the dynamic draws: no static vertex is copied per frame.
        SceneMeshes result;
        if (dc_status s = capi::reconstruct_status("dc_add_dynamic_elements",
                                                   add_dynamic_elements(static_meshes->document.meshes, scene->scene, dynamic, dynamic_analyses, &result)))
            return s;
        frame->document.meshes = std::move(result);
        frame->document.images = scene->scene.images;
        // Nothing of what the object held before (a frame may be any dc_meshes).
        frame->document.animations.clear();
        frame->document.animated.clear();
        frame->seconds = 0;
        return DC_OK;
    });
}

} // extern "C"
