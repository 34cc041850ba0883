// depthcull bench --sprites / --bunnymark: loads each scene as bench does,
// measures it with render::measure_sprites and prints the per-frame table
// (or JSON).
#ifdef DEPTHCULL_HAVE_RENDER
#include "bench_sprites.h"

#include <cstdio>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "depthcull/cost.h"
#include "depthcull/target.h"
#include "outputs.h"
#include "progress.h"
#include "target_common.h"

namespace depthcull::cli {

namespace {

nlohmann::json to_json(const std::string& path, const render::SpriteBenchOptions& options, const render::SpriteMeasurement& m) {
    nlohmann::json frames = nlohmann::json::array();
    for (const auto& f : m.frames) {
        nlohmann::json modes = nlohmann::json::object();
        for (int k = 0; k < 3; ++k) {
            const render::SpriteFrameMeasurement& r = f[std::size_t(k)];
            modes[render::sprite_mode_name(render::SpriteMode(k))] = {{"draw_calls", r.draw_calls}, {"triangles", r.triangles},
                                                                       {"fragments_shaded", r.fragments_shaded}, {"cpu_ms", r.cpu_ms},
                                                                       {"pixels_differ", r.pixels_differ}, {"pixels_differ_off_texel_edges", r.off_texel_edges}};
        }
        frames.push_back(std::move(modes));
    }
    return {{"scene", path},
            {"sprites", options.sprites},
            {"bunnymark", options.bunnymark},
            {"seed", options.seed},
            {"camera", {{"x", m.camera.x}, {"y", m.camera.y}, {"width", m.camera.width}, {"height", m.camera.height}}},
            {"static_elements", m.static_elements},
            {"insertion_element", m.insertion_element},
            {"scene_insertion_point", m.scene_point},
            {"pictures", m.pictures},
            {"pictures_with_opaque", m.pictures_with_opaque},
            {"layers_behind", m.layers_behind},
            {"frames", std::move(frames)}};
}

std::string layers_text(double layers) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", layers);
    return text;
}

// What measure_sprites is asked for; with --target, options.target points
// to *profile.
render::SpriteBenchOptions sprite_options(const SpriteBenchArgs& args, CostProfile* profile) {
    render::SpriteBenchOptions options;
    options.sprites = args.bunnymark > 0 ? args.bunnymark : args.sprites;
    options.bunnymark = args.bunnymark > 0;
    options.frames = args.frames;
    options.seed = args.seed;
    if (!args.input->target.empty()) {
        *profile = resolve_cli_target(args.input->target, args.quiet);
        options.target = profile;
    }
    return options;
}

// One scene: prepared as optimize prepares it, then its sprites drawn.
render::SpriteMeasurement measure_scene(const std::string& path, const RenderInput& input, const render::SpriteBenchOptions& options,
                                        render::GlHost& host, RunOutputs& outputs, Progress& progress) {
    progress.stage(path + ": analyzing");
    // The static scene as optimize prepares it; the target prices the sprites here, not the scene.
    RenderInput scene_input = input;
    scene_input.target.clear();
    const pipeline::OptimizeResult result = optimize_for_render(path, scene_input, true);
    const pipeline::PreparedScene& prepared = result.prepared;
    outputs.add_inputs(scene_inputs(path, prepared.scene, prepared.documents));
    progress.stage(path + ": drawing sprites");
    try {
        return render::measure_sprites(host, prepared.scene, image_views(prepared), prepared.analysis, options);
    } catch (const render::Error& e) {
        throw CliError(path + ": " + e.what());
    }
}

// The two comment lines above a scene's table.
std::string scene_header(const std::string& path, const render::SpriteBenchOptions& options, const render::SpriteMeasurement& m,
                         const std::string& target, const std::string& renderer, const char* lp_threads) {
    char header[1024];
    const std::string where = options.bunnymark ? std::string("alone (bunnymark: no static scene)")
                              : m.scene_point ? "before static element " + std::to_string(m.insertion_element) + " (the scene's first insertion point)"
                                              : std::string("on top (the scene has no insertion point)");
    std::snprintf(header, sizeof header,
                  "# %s: %d moving sprites of %zu pictures (%zu with opaque polygons%s), %s; camera %g,%g %dx%d, %zu static elements on it;\n"
                  "# %s, LP_NUM_THREADS=%s, %d frames, modes in turns frame by frame, seed %u\n",
                  path.c_str(), options.sprites, m.pictures, m.pictures_with_opaque,
                  target.empty() ? "" : (", --target " + target + ": those that pay over " + layers_text(m.layers_behind) + " layers behind").c_str(),
                  where.c_str(), m.camera.x, m.camera.y, m.camera.width, m.camera.height, m.static_elements, renderer.c_str(),
                  lp_threads ? lp_threads : "", options.frames, options.seed);
    return header;
}

// Below the tables: what their columns mean.
constexpr const char* kLegend =
    "# plain batching: each element on the camera as its rect, painter's order, runs of one texture and blend merged, no depth;\n"
    "# meshes only: static meshes reordered and batched once, sprites' boundary polygons batched per frame, no opaque pass;\n"
    "# depth-culled: static meshes with the sprites' depth range reserved + FrameAssembler, opaque pass front to back first;\n"
    "# draws, tris: as drawn (static + moving); fragments: shaded (GL_SAMPLES_PASSED); cpu ms: process CPU time building\n"
    "#   the frame's geometry, drawing it and glFinish; diff/off: pixels differing from the overpaint of the same layers,\n"
    "#   and of those the ones whose centre is on no texel edge (must be 0).\n";

} // namespace

void run_sprite_bench(const SpriteBenchArgs& args) {
    if (args.sprites > 0 && args.bunnymark > 0) throw UsageError("bench: --sprites and --bunnymark: give one");
    const RenderInput& input = *args.input;
    const char* lp_threads = pin_lp_threads(args.lp_threads);
    CostProfile profile;
    const render::SpriteBenchOptions options = sprite_options(args, &profile);
    const std::string target = options.target ? profile.name : std::string();
    RunOutputs outputs(args.scenes);
    outputs.add_inputs(target_inputs(args.input->target));
    outputs.add(args.output);
    auto host = open_host(input.platform);
    std::string text;
    nlohmann::json scenes = nlohmann::json::array();
    Progress progress("bench", "scenes", args.scenes.size(), args.quiet);
    for (const std::string& path : args.scenes) {
        const render::SpriteMeasurement m = measure_scene(path, input, options, *host, outputs, progress);
        if (args.json) scenes.push_back(to_json(path, options, m));
        else text += scene_header(path, options, m, target, host->description(), lp_threads) + render::sprite_table(m);
        progress.add();
    }
    progress.finish();
    if (args.json)
        text = nlohmann::json{{"renderer", host->description()}, {"lp_num_threads", lp_threads ? lp_threads : ""}, {"target", target}, {"scenes", scenes}}
                   .dump(1) +
               "\n";
    else text += kLegend;
    outputs.stage(args.output.empty() ? "-" : args.output, text);
    outputs.commit();
}

} // namespace depthcull::cli
#endif
