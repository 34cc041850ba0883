// depthcull render: draw one frame of a scene headlessly (overpaint,
// meshes only, or optimized), prove it looks like overpaint, and picture
// where the overdraw goes.
#include <cinttypes>
#include <cstdio>
#include <map>

#include "cli.h"

#ifdef DEPTHCULL_HAVE_RENDER
#include "outputs.h"
#include "render_common.h"
#include "target_common.h"
#endif

namespace depthcull::cli {

#ifdef DEPTHCULL_HAVE_RENDER
namespace {

struct RenderArgs {
    std::string scene;
    render::Mode mode = render::Mode::optimized;
    std::string output;
    std::string heatmap;
    bool compare = false;
    RenderInput input;
};

std::string title(const char* name, double overdraw) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s  OD %.2f", name, overdraw);
    return buf;
}

// exact: with coverage skirts (render::exact_coverage), for comparing frames.
SceneMeshes meshes_for(render::Mode mode, const pipeline::OptimizeResult& result, const RenderArgs& args, bool exact = false) {
    SceneMeshes meshes;
    ReconstructOptions options = result.reconstruct;
    if (exact) options = render::exact_coverage(options);
    switch (render::build_meshes(mode, result.prepared.scene, result.prepared.analysis, options, &meshes)) {
    case ReconstructStatus::ok: return meshes;
    case ReconstructStatus::invalid_scene: throw CliError(args.scene + ": invalid scene for reconstruction");
    case ReconstructStatus::too_many_depth_levels:
        throw CliError(args.scene + ": more than " + std::to_string(kMaxDepthLevels) + " depth levels for a 24-bit depth buffer");
    }
    return meshes;
}

// Overpaint | the mode drawn (optimized when that is overpaint) | ideal,
// all counted by the CPU analyzer, which needs no GL.
void write_heatmap(const pipeline::OptimizeResult& result, const SceneMeshes& drawn, const RenderArgs& args, RunOutputs& outputs) {
    const pipeline::PreparedScene& prepared = result.prepared;
    OverdrawMap over, other, ideal;
    const double od_over = analyze_overdraw(overpaint_meshes(prepared.scene), &over).overdraw();
    render::Mode other_mode = args.mode == render::Mode::overpaint ? render::Mode::optimized : args.mode;
    const SceneMeshes other_meshes = args.mode == render::Mode::overpaint ? meshes_for(other_mode, result, args) : drawn;
    const double od_other = analyze_overdraw(other_meshes, &other).overdraw();
    const double od_ideal = ideal_overdraw(prepared.scene, image_views(prepared), &ideal).overdraw();
    Image picture = report::overdraw_heatmap({{title("overpaint", od_over), &over},
                                              {title(render::mode_name(other_mode), od_other), &other},
                                              {title("ideal", od_ideal), &ideal}});
    outputs.stage(args.heatmap, io::encode_png(picture.view()));
}

void run_render(RenderArgs& args) {
    if (args.output.empty() && args.heatmap.empty() && !args.compare)
        throw UsageError("render: nothing to do: give -o FRAME.png, --heatmap HEAT.png or --compare");
    // Checked first, committed together once all is drawn: a failure
    // (no GL context, a frame too large) writes neither file.
    RunOutputs outputs({args.scene});
    outputs.add_inputs(target_inputs(args.input.target));
    outputs.add(args.output);
    outputs.add(args.heatmap);
    const pipeline::OptimizeResult result = optimize_for_render(args.scene, args.input, false);
    const pipeline::PreparedScene& prepared = result.prepared;
    check_frame_fits(args.scene, prepared, args.input);
    outputs.add_inputs(scene_inputs(args.scene, prepared.scene, prepared.documents));
    const SceneMeshes meshes = meshes_for(args.mode, result, args);
    if (!args.heatmap.empty()) write_heatmap(result, meshes, args, outputs);
    if (args.output.empty() && !args.compare) return outputs.commit();

    auto renderer = open_renderer(args.input);
    renderer->set_images(image_views(prepared), prepared.scene.filter);
    const std::vector<TexelMap> maps = element_maps(prepared.scene);
    renderer->set_meshes(meshes, maps);
    const render::FrameCounts counts = renderer->draw_counted();
    const Image frame = renderer->read_pixels();
    if (!args.output.empty()) outputs.stage(args.output, io::encode_png(frame.view()));

    const double pixels = double(prepared.scene.viewport.width) * double(prepared.scene.viewport.height);
    OverdrawMap ideal_map;
    const double ideal = ideal_overdraw(prepared.scene, image_views(prepared), &ideal_map).overdraw();
    const double od = double(counts.samples_passed) / pixels;
    std::fprintf(stderr,
                 "depthcull: %s: %s: %" PRId64 " draw calls, %" PRId64 " triangles, overdraw %.3f (ideal %.3f, %.2fx; fragments shaded "
                 "over all %dx%d viewport pixels, %.1f%% of them covered), %s\n",
                 args.scene.c_str(), render::mode_name(args.mode), counts.draw_calls, counts.triangles, od, ideal,
                 ideal > 0 ? od / ideal : 0.0, prepared.scene.viewport.width, prepared.scene.viewport.height, 100 * covered_share(ideal_map),
                 renderer->description().c_str());
    // Committed before the comparison: the files are whole and right, and a
    // frame that differs from overpaint is what one wants to look at.
    outputs.commit();
    if (!args.compare) return;

    // Both frames drawn from meshes with coverage skirts, where GL's vertex
    // snapping cannot decide a pixel (render.h, kCoverageMargin).
    const SceneMeshes overpaint = meshes_for(render::Mode::overpaint, result, args, true);
    const SceneMeshes exact = meshes_for(args.mode, result, args, true);
    renderer->set_meshes(overpaint, maps);
    renderer->draw();
    const Image reference = renderer->read_pixels();
    renderer->set_meshes(exact, maps);
    renderer->draw();
    const Image compared = renderer->read_pixels();
    const render::ImageDiff diff = render::compare_images(reference.view(), compared.view());
    const bool nearest = prepared.scene.filter == Filter::nearest;
    if (diff.pixels_differ == 0) {
        std::fprintf(stderr, "depthcull: %s: %s frame equals the overpaint frame pixel for pixel (RGBA, %s filtering)\n",
                     args.scene.c_str(), render::mode_name(args.mode), nearest ? "nearest" : "linear");
        return;
    }
    const render::DiffCauses causes = render::classify_differences(reference.view(), overpaint, compared.view(), exact, &prepared.scene);
    const std::string text = args.scene + ": " + render::mode_name(args.mode) + " frame differs from overpaint in " +
                             std::to_string(diff.pixels_differ) + " pixels (largest channel difference " +
                             std::to_string(diff.max_channel_diff) + "): " + std::to_string(causes.near_edges) +
                             " within 1/64 pixel of a triangle or texel edge, where rounding decides coverage or texel, " +
                             std::to_string(causes.elsewhere) + " elsewhere" + (nearest ? "" : " (linear filtering)");
    // With nearest filtering any difference is a bug: every element samples
    // through its one texel map whatever triangles cover it, so not even a
    // pixel centre on a texel edge may differ (the edge split stays as a
    // clue to the cause). Bilinear filtering legitimately differs along
    // polygon edges, so it is reported only.
    if (nearest) throw CliError(text);
    std::fprintf(stderr, "depthcull: %s\n", text.c_str());
}

} // namespace

void add_render_command(CLI::App& app) {
    auto args = std::make_shared<RenderArgs>();
    auto* cmd = app.add_subcommand("render", "Draw a scene headlessly (EGL, OpenGL) and compare it with overpaint");
    cmd->add_option("scene", args->scene, "Scene: .json (our format) or .tmx / .tmx.gz (Tiled)")->required();
    cmd->add_option("--mode", args->mode, "overpaint (unoptimized), meshes (meshes only) or optimized (default)")
        ->transform(choice<render::Mode>({
            {"overpaint", render::Mode::overpaint}, {"meshes", render::Mode::meshes}, {"optimized", render::Mode::optimized}}))
        ->default_str("optimized");
    cmd->add_option("-o,--output", args->output, "PNG of the frame (RGBA, viewport size)");
    cmd->add_option("--heatmap", args->heatmap, "PNG of overdraw per pixel: overpaint | this mode | ideal, with a legend");
    cmd->add_flag("--compare", args->compare,
                  "Also draw overpaint and compare; with nearest filtering any difference is an error (exit 1)");
    add_render_input_options(*cmd, args->input);
    cmd->callback([args] { run_render(*args); });
}

#else

void add_render_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("render", "Draw a scene headlessly (not in this build)");
    cmd->allow_extras();
    cmd->callback([] { throw CliError("render: this depthcull was built without the renderer (DEPTHCULL_BUILD_RENDER=OFF)"); });
}

#endif

} // namespace depthcull::cli
