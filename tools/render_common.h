// What `render` and `bench` share: loading and analyzing a scene the way
// `optimize` does (same options, same cache), and opening the renderer.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cli.h"
#include "depthcull/io.h"
#include "depthcull/overdraw.h"
#include "depthcull/pipeline.h"
#include "depthcull/render.h"

namespace depthcull::cli {

struct RenderInput {
    pipeline::PrepareOptions prepare;
    CacheChoice cache;
    ReconstructOptions reconstruct;
    bool opaque = true;
    render::GlPlatform platform = render::GlPlatform::automatic;
    CLI::Option* filter_option = nullptr;
    std::string target;        // --target PROFILE (target_common.h)
};

// --cache, --no-cache, --graph, --sort, --no-opaque, --viewport, the
// analysis options, -j, --gl.
void add_render_input_options(CLI::App& command, RenderInput& input);

// The prepare options the input stands for (--filter an override, the cache).
pipeline::PrepareOptions prepare_options(const RenderInput& input);
pipeline::PreparedScene prepare_for_render(const std::string& scene, const RenderInput& input);
ReconstructOptions reconstruct_options(const RenderInput& input);
std::vector<ImageView> image_views(const pipeline::PreparedScene& prepared);

// Throws CliError("no OpenGL context: ...") when none can be made.
std::unique_ptr<render::GlRenderer> open_renderer(const RenderInput& input);

// apply_target (target_common.h) for render, bench and report: the prepare
// options of prepare_for_render, and input.opaque set as chosen.
std::unique_ptr<pipeline::TargetPlan> apply_render_target(const std::string& path, pipeline::PreparedScene& prepared, RenderInput& input, bool quiet);

} // namespace depthcull::cli

#ifdef DEPTHCULL_HAVE_RENDER
#include "depthcull/report.h"

namespace depthcull::cli {

// Share of viewport pixels where some element shows a non-transparent
// texel (the ideal map's non-zero pixels): overdraw is fragments over all
// viewport pixels, so this says how much of that denominator is empty.
double covered_share(const OverdrawMap& ideal);

// One scene's section of the HTML report from what bench measured (one of
// rt / m, with frames kept): Table 2 rows, frames, heatmaps (CPU
// analyzers), per-image table with previews.
report::SceneReport scene_report(const std::string& path, const pipeline::PreparedScene& prepared, const RenderInput& input,
                                 const render::RuntimeMeasurement* rt, const render::SceneMeasurement* m);
// The options section: analysis, reconstruction, frames, LP_NUM_THREADS.
std::vector<std::pair<std::string, std::string>> report_options(const RenderInput& input, int frames, int warmup, const char* shader);

// A scene's drawn extent must fit the frame: a scene with no viewport
// whose elements span more than kMaxImageSide got a clamped viewport, and
// rendering it would silently show only part of it.
void check_frame_fits(const std::string& path, const pipeline::PreparedScene& prepared, const RenderInput& input);

} // namespace depthcull::cli
#endif
