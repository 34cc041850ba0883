// depthcull.h: errors and per-image analysis (paper 2.1, 2.2).
#include <cmath>
#include <cstring>
#include <type_traits>

#include "capi/capi_internal.h"
#include "depthcull/analyze.h"

namespace depthcull::capi {

namespace {
thread_local std::string last_error;
} // namespace

dc_status fail(dc_status status, const char* message, const char* detail) noexcept {
    try {
        last_error = message ? message : "";
        if (detail) last_error.append(": ").append(detail);
    } catch (...) {
        last_error.clear(); // out of memory for the message itself: the status still says what happened
    }
    return status;
}

dc_status reconstruct_status(const char* function, ReconstructStatus status) {
    switch (status) {
    case ReconstructStatus::ok: return DC_OK;
    case ReconstructStatus::invalid_scene:
        return fail(DC_ERROR_INVALID_SCENE, function,
                    "the scene was refused (an element without an analysis, or meshes without depth levels for dynamic elements)");
    case ReconstructStatus::too_many_depth_levels:
        return fail(DC_ERROR_TOO_MANY_DEPTH_LEVELS, function,
                    "more depth levels than a 24-bit depth buffer resolves, or more dynamic elements than the reserved levels");
    }
    return fail(DC_ERROR_INTERNAL, function, "unknown reconstruction status");
}

} // namespace depthcull::capi

using namespace depthcull;
using depthcull::capi::fail;
using depthcull::capi::guard;

// dc_point is read straight out of the analysis' polygons.
static_assert(sizeof(dc_point) == sizeof(Vec2) && std::is_standard_layout_v<Vec2> && offsetof(dc_point, y) == offsetof(Vec2, y));

extern "C" {

const char* dc_last_error(void) { return capi::last_error.c_str(); }

const char* dc_status_string(dc_status status) {
    switch (status) {
    case DC_OK: return "ok";
    case DC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case DC_ERROR_INVALID_SCENE: return "invalid scene";
    case DC_ERROR_TOO_MANY_DEPTH_LEVELS: return "too many depth levels";
    case DC_ERROR_IO: return "i/o error";
    case DC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case DC_ERROR_INTERNAL: return "internal error";
    case DC_ERROR_GL: return "OpenGL error";
    case DC_ERROR_UNSUPPORTED: return "not in this build";
    }
    return "unknown status";
}

void dc_analyze_options_default(dc_analyze_options* options) {
    if (!options) return;
    const AnalyzeOptions d;
    options->max_boundary_vertices = d.boundary.max_vertices;
    options->filter = d.filter == Filter::linear ? DC_FILTER_LINEAR : DC_FILTER_NEAREST;
    options->split_parts = d.boundary.split_parts;
    options->opaque_method = d.opaque.method == OpaqueMethod::paper ? DC_OPAQUE_PAPER : d.opaque.method == OpaqueMethod::grow ? DC_OPAQUE_GROW : DC_OPAQUE_FAST;
    options->max_opaque_polygons = d.opaque.max_polygons;
    options->min_opaque_coverage = d.opaque.min_coverage;
    options->min_opaque_area = d.opaque.min_area;
}

} // extern "C"

namespace {

// Empty when the options are usable, else why not.
std::string options_problem(const dc_analyze_options& o) {
    if (o.max_boundary_vertices < 0 || o.max_boundary_vertices > 1024) return "max_boundary_vertices must be 0..1024";
    if (o.filter != DC_FILTER_NEAREST && o.filter != DC_FILTER_LINEAR) return "filter must be DC_FILTER_NEAREST or DC_FILTER_LINEAR";
    if (o.opaque_method < DC_OPAQUE_PAPER || o.opaque_method > DC_OPAQUE_GROW) return "opaque_method must be a dc_opaque_method";
    if (o.max_opaque_polygons < 0 || o.max_opaque_polygons > 1024) return "max_opaque_polygons must be 0..1024";
    if (!(o.min_opaque_coverage >= 0 && o.min_opaque_coverage <= 1)) return "min_opaque_coverage must be in 0..1";
    if (o.min_opaque_area < 0) return "min_opaque_area must not be negative";
    return {};
}

AnalyzeOptions to_options(const dc_analyze_options& o) {
    AnalyzeOptions a;
    const Filter filter = o.filter == DC_FILTER_LINEAR ? Filter::linear : Filter::nearest;
    a.boundary.max_vertices = o.max_boundary_vertices;
    a.filter = filter;
    a.boundary.split_parts = o.split_parts != 0;
    a.opaque.method = o.opaque_method == DC_OPAQUE_PAPER ? OpaqueMethod::paper : o.opaque_method == DC_OPAQUE_GROW ? OpaqueMethod::grow : OpaqueMethod::fast;
    a.opaque.max_polygons = o.max_opaque_polygons;
    a.opaque.min_coverage = o.min_opaque_coverage;
    a.opaque.min_area = o.min_opaque_area;
    return a;
}

const Polygon* polygon(const std::vector<Polygon>& polygons, std::size_t i, std::size_t* count) {
    const Polygon* p = i < polygons.size() ? &polygons[i] : nullptr;
    if (count) *count = p ? p->size() : 0;
    return p;
}

} // namespace

extern "C" {

dc_status dc_analyze_image(const uint8_t* rgba, int width, int height, ptrdiff_t stride, dc_rect rect,
                           const dc_analyze_options* options, dc_analysis** out) {
    return guard("dc_analyze_image", [&] {
        if (!rgba || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_analyze_image: rgba and out must not be NULL");
        if (width <= 0 || height <= 0 || width > kMaxImageSide || height > kMaxImageSide || std::int64_t(width) * height > kMaxImageTexels)
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_analyze_image: image size " + std::to_string(width) + "x" + std::to_string(height) +
                                                       " is outside 1.." + std::to_string(kMaxImageSide) + " per side");
        if (stride < ptrdiff_t(width) * 4) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_analyze_image: stride is less than 4 * width");
        const ImageView view{rgba, width, height, stride};
        const Rect r{rect.x, rect.y, rect.w, rect.h};
        if (r.empty() || !view.contains(r))
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_analyze_image: rect is empty or outside the " + std::to_string(width) + "x" +
                                                       std::to_string(height) + " image");
        dc_analyze_options o;
        dc_analyze_options_default(&o);
        if (options) o = *options;
        if (std::string problem = options_problem(o); !problem.empty()) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_analyze_image: " + problem);
        auto handle = std::make_unique<dc_analysis>();
        handle->analysis = std::make_shared<const ImageAnalysis>(analyze_image(view, r, to_options(o)));
        *out = handle.release();
        return DC_OK;
    });
}

void dc_analysis_destroy(dc_analysis* analysis) { delete analysis; }

dc_rect dc_analysis_rect(const dc_analysis* analysis) {
    if (!analysis) return dc_rect{0, 0, 0, 0};
    const Rect& r = analysis->analysis->rect;
    return dc_rect{r.x, r.y, r.w, r.h};
}

size_t dc_analysis_boundary_count(const dc_analysis* analysis) { return analysis ? analysis->analysis->boundary.size() : 0; }
size_t dc_analysis_opaque_count(const dc_analysis* analysis) { return analysis ? analysis->analysis->opaque.size() : 0; }

const dc_point* dc_analysis_boundary(const dc_analysis* analysis, size_t i, size_t* count) {
    const Polygon* p = analysis ? polygon(analysis->analysis->boundary, i, count) : polygon({}, 0, count);
    return p ? reinterpret_cast<const dc_point*>(p->data()) : nullptr;
}

const dc_point* dc_analysis_opaque(const dc_analysis* analysis, size_t i, size_t* count) {
    const Polygon* p = analysis ? polygon(analysis->analysis->opaque, i, count) : polygon({}, 0, count);
    return p ? reinterpret_cast<const dc_point*>(p->data()) : nullptr;
}

dc_status dc_analysis_stats(const dc_analysis* analysis, dc_image_stats* out) {
    if (!analysis || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_analysis_stats: analysis and out must not be NULL");
    const ImageStats& s = analysis->analysis->stats;
    *out = dc_image_stats{s.nontransparent_texels, s.opaque_texels, s.boundary_area, s.boundary_vertices, s.opaque_area,
                          s.opaque_covered_texels, s.opaque_coverage};
    return DC_OK;
}

} // extern "C"
