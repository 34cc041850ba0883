// What `render` and `bench` share: loading and analyzing a scene the way
// `optimize` does (same options, same cache), and opening the renderer.
#pragma once

#include <functional>
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
    std::string target;        // --target PROFILE (target_common.h)
};

// --cache, --no-cache, --graph, --sort, --no-opaque, --viewport, the
// analysis options, -j, --gl.
void add_render_input_options(CLI::App& command, RenderInput& input);

// What the input asks pipeline::optimize for: the analysis and its cache,
// the reconstruction, the target; no meshes (each mode's are built for
// drawing, from OptimizeResult::reconstruct).
pipeline::OptimizeOptions optimize_options(const RenderInput& input);
// pipeline::optimize with those options; prints pipeline::target_summary
// on stderr for a target unless quiet. `stage`: progress lines.
pipeline::OptimizeResult optimize_for_render(const std::string& path, const RenderInput& input, bool quiet,
                                             const std::function<void(const char*)>& stage = {});
std::vector<ImageView> image_views(const pipeline::PreparedScene& prepared);

// Throws CliError("no OpenGL context: ... (headless rendering needs
// Mesa's EGL: ...)") when none can be made; other render::Errors pass.
std::unique_ptr<render::GlRenderer> open_renderer(const RenderInput& input);
// The same for a desktop GL host of depthcull::runtime.
std::unique_ptr<render::GlHost> open_host(render::GlPlatform platform);

// llvmpipe reads LP_NUM_THREADS when a context is made; pinned before one
// is, so that timings of runs and machines compare: `lp_threads` when >= 0
// (--lp-threads), else the environment's, else 1. Returns what is in force.
const char* pin_lp_threads(int lp_threads);

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
report::SceneReport scene_report(const std::string& path, const pipeline::OptimizeResult& result, const render::RuntimeMeasurement* rt,
                                 const render::SceneMeasurement* m);
// The options section: analysis, reconstruction, frames, LP_NUM_THREADS.
std::vector<std::pair<std::string, std::string>> report_options(const RenderInput& input, int frames, int warmup, const char* shader);

// A scene's drawn extent must fit the frame: a scene with no viewport
// whose elements span more than kMaxImageSide got a clamped viewport, and
// rendering it would silently show only part of it.
void check_frame_fits(const std::string& path, const pipeline::PreparedScene& prepared, const RenderInput& input);

} // namespace depthcull::cli
#endif
