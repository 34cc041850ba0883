// depthcull bench: the paper's Table 2 for our scenes, measured by
// drawing: draw calls, triangles, fragments rasterized and shaded
// (GL_SAMPLES_PASSED), the ideal overdraw, wall and CPU milliseconds per
// frame and the pixel difference against overpaint, for overpaint, meshes
// only and optimized. Frames are drawn by depthcull::runtime, the plain
// sprite shader an engine runs; --renderer instrumented times the
// measuring renderer of `render --compare` instead (texel maps and rect
// tests in its shader), for comparison.
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli.h"

#include "progress.h"

#ifdef DEPTHCULL_HAVE_RENDER
#include "bench_sprites.h"
#include "outputs.h"
#include "render_common.h"
#include "target_common.h"
#endif

namespace depthcull::cli {

#ifdef DEPTHCULL_HAVE_RENDER
namespace {

using nlohmann::json;

struct BenchArgs {
    std::vector<std::string> scenes;
    int frames = 20;
    int warmup = 3;
    bool json_output = false;
    std::string output;
    std::string modes = "overpaint,meshes,optimized";
    int lp_threads = -1;
    enum class Shader { runtime, instrumented } shader = Shader::runtime;
    bool instrumented = false; // shader == instrumented, set when run
    RenderInput input;
    std::string report;        // --report FILE (bench), -o FILE (report)
    bool report_only = false;  // `depthcull report`: no table
    bool quiet = false;
    bool opaque_given = true;  // --no-opaque as given (a --target choice changes input.opaque per scene)
    int sprites = 0, bunnymark = 0; // --sprites N, --bunnymark N: bench_sprites.h
    std::uint32_t seed = 23;
    CLI::Option* frames_option = nullptr;
};

// The modes in the order measure_runtime reports them: as asked, once each.
std::vector<render::Mode> modes_in_order(const std::vector<render::Mode>& modes) {
    std::vector<render::Mode> order{render::Mode::overpaint}, out;
    for (render::Mode m : modes)
        if (std::find(order.begin(), order.end(), m) == order.end()) order.push_back(m);
    for (render::Mode m : order)
        if (std::find(modes.begin(), modes.end(), m) != modes.end()) out.push_back(m);
    return out;
}

std::vector<render::Mode> parse_modes(const std::string& text) {
    static const std::map<std::string, render::Mode> names{
        {"overpaint", render::Mode::overpaint}, {"meshes", render::Mode::meshes}, {"optimized", render::Mode::optimized}};
    std::vector<render::Mode> modes;
    std::stringstream in(text);
    for (std::string name; std::getline(in, name, ',');) {
        auto it = names.find(name);
        if (it == names.end()) throw UsageError("bench: --modes: unknown mode '" + name + "' (overpaint, meshes, optimized)");
        modes.push_back(it->second);
    }
    if (modes.empty()) throw UsageError("bench: --modes: no modes given");
    return modes;
}

struct SceneResult {
    std::string path;
    std::size_t elements = 0;
    render::SceneMeasurement m;        // --renderer instrumented
    render::RuntimeMeasurement rt;     // the runtime renderer
    double covered = 0;                // share of viewport pixels showing a non-transparent texel
    std::vector<double> predicted;     // --target: predicted ms per mode of rt.modes
    std::vector<FrameFeatures> features; // --target: what the model read off each mode's meshes
    std::vector<CostTerms> terms;      // --target: the prediction by term
    std::string target;                // the profile's name
    double limit_ms = 0;               // --target: the ideal frame's predicted ms (limit_ms, issue 25)
    FrameFeatures limit;               // --target: what limit_ms priced (with the ideal frame's blocks)
};

// The model's prediction for each mode drawn (the meshes measure_runtime draws).
void predict_modes(const pipeline::PreparedScene& prepared, const render::MeasureOptions& options, const CostProfile& profile,
                   const std::vector<render::Mode>& modes, SceneResult* r) {
    std::vector<double>& out = r->predicted;
    ReconstructOptions reconstruct = options.reconstruct;
    reconstruct.coverage_margin = 0;
    for (render::Mode mode : modes) {
        SceneMeshes meshes;
        if (render::build_meshes(mode, prepared.scene, prepared.analysis, reconstruct, &meshes, true) != ReconstructStatus::ok) {
            out.push_back(0);
            r->features.emplace_back();
            r->terms.emplace_back();
            continue;
        }
        r->features.push_back(frame_features(meshes, /*count_blocks=*/true));
        r->terms.push_back(predict_terms(profile, r->features.back()));
        out.push_back(predict_ms(profile, r->features.back()));
    }
    r->limit = limit_features(prepared.scene, prepared.views());
    r->limit_ms = predict_ms(profile, r->limit);
}

double median_of(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

std::string short_path(const std::string& path) { return path.size() > 24 ? "..." + path.substr(path.size() - 21) : path; }

std::string runtime_table(const std::vector<SceneResult>& results) {
    std::string out;
    char line[512];
    const bool predicted = !results.empty() && !results.front().predicted.empty();
    std::snprintf(line, sizeof line, "%-24s %-10s %7s %8s %7s %7s %7s %8s %7s %9s %9s %7s %7s%s\n", "Scene", "Mode", "Obj", "Tri", "raster",
                  "OD", "ideal", "OD/ideal", "covered", "ms", "cpu ms", "diffpx", "offedge", predicted ? "   pred ms   error  /limit /overpaint" : "");
    out += line;
    for (const SceneResult& r : results) {
        const double pixels = double(r.rt.width) * double(r.rt.height);
        for (std::size_t mi = 0; mi < r.rt.modes.size(); ++mi) {
            const render::RuntimeModeMeasurement& m = r.rt.modes[mi];
            const double od = pixels > 0 ? double(m.fragments_shaded) / pixels : 0;
            std::snprintf(line, sizeof line, "%-24s %-10s %7" PRId64 " %8" PRId64 " %7.3f %7.3f %7.3f %8.3f %6.1f%% %9.3f %9.3f %7" PRId64 " %7" PRId64,
                          short_path(r.path).c_str(), render::mode_name(m.mode), m.draw_calls, m.triangles,
                          pixels > 0 ? double(m.fragments_rasterized) / pixels : 0, od, r.rt.ideal_overdraw,
                          r.rt.ideal_overdraw > 0 ? od / r.rt.ideal_overdraw : 0.0, 100 * r.covered, m.wall_ms, m.cpu_ms, m.diff.pixels_differ,
                          m.off_texel_edges);
            out += line;
            if (mi < r.predicted.size()) {
                const double over = r.rt.modes[0].mode == render::Mode::overpaint ? r.rt.modes[0].cpu_ms : 0; // first when drawn
                std::snprintf(line, sizeof line, " %9.3f %6.1f%% %7.3f %10.3f", r.predicted[mi], m.cpu_ms > 0 ? 100 * (r.predicted[mi] - m.cpu_ms) / m.cpu_ms : 0.0,
                              r.limit_ms > 0 ? m.cpu_ms / r.limit_ms : 0.0, over > 0 ? m.cpu_ms / over : 0.0);
                out += line;
            }
            out += "\n";
        }
    }
    return out;
}

// Median of |predicted - measured CPU| / measured over every scene and mode.
double median_prediction_error(const std::vector<SceneResult>& results) {
    std::vector<double> errors;
    for (const SceneResult& r : results)
        for (std::size_t mi = 0; mi < r.predicted.size() && mi < r.rt.modes.size(); ++mi)
            if (r.rt.modes[mi].cpu_ms > 0) errors.push_back(std::abs(r.predicted[mi] - r.rt.modes[mi].cpu_ms) / r.rt.modes[mi].cpu_ms);
    return median_of(errors);
}

json features_json(const FrameFeatures& f) {
    return {{"pixels", f.pixels},
            {"depth_clear", f.depth_clear},
            {"draw_calls", f.draw_calls},
            {"texture_switches", f.texture_switches},
            {"triangles", f.triangles},
            {"triangle_perimeter", f.triangle_perimeter},
            {"opaque_fragments", f.opaque_fragments},
            {"blend_fragments", f.blend_fragments},
            {"rejected_fragments", f.rejected_fragments},
            {"opaque_blocks", f.opaque_blocks},
            {"blend_blocks", f.blend_blocks}};
}

json runtime_json(const SceneResult& r) {
    json modes = json::array();
    const double pixels = double(r.rt.width) * double(r.rt.height);
    for (std::size_t mi = 0; mi < r.rt.modes.size(); ++mi) {
        const render::RuntimeModeMeasurement& m = r.rt.modes[mi];
        const double od = pixels > 0 ? double(m.fragments_shaded) / pixels : 0;
        if (mi < r.predicted.size()) {
            const FrameFeatures& f = r.features[mi];
            const CostTerms& t = r.terms[mi];
            modes.push_back({{"mode", render::mode_name(m.mode)},
                             {"predicted_ms", r.predicted[mi]},
                             {"cpu_over_limit", r.limit_ms > 0 ? m.cpu_ms / r.limit_ms : 0.0},
                             {"cpu_over_overpaint", r.rt.modes[0].mode == render::Mode::overpaint && r.rt.modes[0].cpu_ms > 0 ? m.cpu_ms / r.rt.modes[0].cpu_ms : 0.0},
                             {"predicted_terms_ms",
                              {{"frame", t.frame}, {"clears", t.clears}, {"draws", t.draws}, {"triangles", t.triangles},
                               {"opaque", t.opaque}, {"blend", t.blend}, {"rejected", t.rejected}}},
                             {"model_features", features_json(f)}});
        } else {
            modes.push_back(json::object());
        }
        modes.back().update(json{{"mode", render::mode_name(m.mode)},
                         {"draw_calls", m.draw_calls},
                         {"triangles", m.triangles},
                         {"fragments_rasterized", m.fragments_rasterized},
                         {"fragments_shaded", m.fragments_shaded},
                         {"fragments_by_texel",
                          {{"transparent", m.excess.transparent}, {"hidden", m.excess.hidden}, {"needed", m.excess.needed}}},
                         {"blocks_by_texel", {{"needed", m.excess.blocks_needed}, {"waste", m.excess.blocks_waste}}},
                         {"samples_passed", m.fragments_shaded},
                         {"rasterized_overdraw", pixels > 0 ? double(m.fragments_rasterized) / pixels : 0},
                         {"overdraw", od},
                         {"overdraw_over_ideal", r.rt.ideal_overdraw > 0 ? od / r.rt.ideal_overdraw : 0.0},
                         {"ms_median", m.wall_ms},
                         {"cpu_ms_median", m.cpu_ms},
                         {"max_channel_diff", m.diff.max_channel_diff},
                         {"pixels_differ", m.diff.pixels_differ},
                         {"pixels_differ_on_texel_edges", m.diff.pixels_differ - m.off_texel_edges},
                         {"pixels_differ_elsewhere", m.off_texel_edges}});
    }
    json scene = {{"scene", r.path},
                  {"target", r.target},
                  {"width", r.rt.width},
                  {"height", r.rt.height},
                  {"elements", r.elements},
                  {"covered", r.covered},
                  {"ideal_overdraw", r.rt.ideal_overdraw},
                  {"limit_ms", r.limit_ms},
                  {"modes", modes}};
    if (!r.predicted.empty()) scene["limit_features"] = features_json(r.limit);
    return scene;
}

std::string table(const std::vector<SceneResult>& results) {
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "%-24s %-10s %7s %8s %7s %7s %8s %7s %9s %9s %7s %7s %7s\n", "Scene", "Mode", "Obj", "Tri", "OD",
                  "ideal", "OD/ideal", "covered", "ms", "min ms", "maxdiff", "diffpx", "offedge");
    out += line;
    for (const SceneResult& r : results) {
        std::string name = short_path(r.path);
        for (const render::ModeMeasurement& mode : r.m.modes) {
            std::snprintf(line, sizeof line, "%-24s %-10s %7" PRId64 " %8" PRId64 " %7.3f %7.3f %8.3f %6.1f%% %9.3f %9.3f %7d %7" PRId64 " %7" PRId64 "\n",
                          name.c_str(), render::mode_name(mode.mode), mode.counts.draw_calls, mode.counts.triangles, mode.overdraw,
                          r.m.ideal_overdraw, r.m.ideal_overdraw > 0 ? mode.overdraw / r.m.ideal_overdraw : 0.0, 100 * r.covered, mode.ms_median, mode.ms_min,
                          mode.diff.max_channel_diff, mode.diff.pixels_differ, mode.causes.elsewhere);
            out += line;
        }
    }
    return out;
}

json to_json(const std::vector<SceneResult>& results, const std::string& renderer, const BenchArgs& args, const char* lp_threads) {
    json scenes = json::array();
    for (const SceneResult& r : results) {
        if (!args.instrumented) {
            scenes.push_back(runtime_json(r));
            continue;
        }
        json modes = json::array();
        for (const render::ModeMeasurement& m : r.m.modes)
            modes.push_back({{"mode", render::mode_name(m.mode)},
                             {"draw_calls", m.counts.draw_calls},
                             {"triangles", m.counts.triangles},
                             {"samples_passed", m.counts.samples_passed},
                             {"overdraw", m.overdraw},
                             {"cpu_overdraw", m.cpu_overdraw},
                             {"overdraw_over_ideal", r.m.ideal_overdraw > 0 ? m.overdraw / r.m.ideal_overdraw : 0.0},
                             {"ms_median", m.ms_median},
                             {"ms_min", m.ms_min},
                             {"max_channel_diff", m.diff.max_channel_diff},
                             {"pixels_differ", m.diff.pixels_differ},
                             {"pixels_differ_near_edges", m.causes.near_edges},
                             {"pixels_differ_elsewhere", m.causes.elsewhere}});
        scenes.push_back({{"scene", r.path},
                          {"width", r.m.width},
                          {"height", r.m.height},
                          {"elements", r.elements},
                          {"covered", r.covered},
                          {"ideal_overdraw", r.m.ideal_overdraw},
                          {"modes", modes}});
    }
    return {{"renderer", renderer},
            {"overdraw_is", "fragments shaded / all viewport pixels (empty pixels count 0); covered: share of viewport pixels showing a "
                            "non-transparent texel"},
            {"shader", args.instrumented ? "instrumented" : "runtime"},
            {"lp_num_threads", lp_threads ? lp_threads : ""},
            {"frames", args.frames},
            {"warmup", args.warmup},
            {"scenes", scenes}};
}

// One scene of a bench (or report) run: optimized through the pipeline,
// drawn by the instrumented renderer or the runtime in every mode, its
// predictions and (for --report) its report section added to `run`.
SceneResult bench_scene(const std::string& path, BenchArgs& args, const std::vector<render::Mode>& modes, render::GlRenderer* renderer,
                        render::GlHost* host, Progress& progress, RunOutputs& outputs, report::RunReport& run) {
    args.input.opaque = args.opaque_given;
    const pipeline::OptimizeResult result =
        optimize_for_render(path, args.input, args.quiet, [&](const char* stage) { progress.stage(path + ": " + stage); });
    const pipeline::PreparedScene& prepared = result.prepared;
    const std::optional<pipeline::TargetPlan>& plan = result.plan;
    // The options section of the report says whether the (last) choice drew the opaque pass.
    args.input.opaque = result.reconstruct.opaque_polygons;
    check_frame_fits(path, prepared, args.input);
    outputs.add_inputs(scene_inputs(path, prepared.scene, prepared.documents));
    progress.stage(path + ": drawing");
    render::MeasureOptions options;
    options.modes = modes;
    options.frames = args.frames;
    options.warmup = args.warmup;
    options.reconstruct = result.reconstruct;
    options.keep_frames = !args.report.empty();
    SceneResult r;
    r.path = path;
    if (plan) {
        r.target = plan->profile.name;
        predict_modes(prepared, options, plan->profile, renderer ? std::vector<render::Mode>{} : modes_in_order(modes), &r);
    }
    r.elements = prepared.scene.elements.size();
    try {
        if (renderer)
            r.m = render::measure_scene(*renderer, prepared.scene, image_views(prepared), prepared.analysis, options);
        else
            r.rt = render::measure_runtime(*host, prepared.scene, image_views(prepared), prepared.analysis, options);
    } catch (const render::Error& e) {
        throw CliError(path + ": " + e.what());
    }
    if (!args.report.empty()) {
        progress.stage(path + ": report");
        run.scenes.push_back(scene_report(path, result, renderer ? nullptr : &r.rt, renderer ? &r.m : nullptr));
        if (!r.predicted.empty()) {
            // Same order: predict_modes predicted rt.modes' modes.
            report::SceneReport& sr = run.scenes.back();
            sr.target = r.target;
            sr.limit_ms = r.limit_ms;
            for (std::size_t mi = 0; mi < sr.rows.size() && mi < r.predicted.size(); ++mi) sr.rows[mi].predicted_ms = r.predicted[mi];
        }
        r.covered = run.scenes.back().covered;
        // The frames live on in the report; drop them here.
        for (auto& mode : r.m.modes) mode.frame = {};
        for (auto& mode : r.rt.modes) mode.frame = {};
    } else {
        OverdrawMap ideal;
        ideal_overdraw(prepared.scene, image_views(prepared), &ideal);
        r.covered = covered_share(ideal);
    }
    return r;
}

// The bench's table (or JSON) with the notes on its columns.
std::string bench_text(const std::vector<SceneResult>& results, const std::string& description, const BenchArgs& args, const char* lp_threads) {
    std::string text;
    if (args.json_output) {
        text = to_json(results, description, args, lp_threads).dump(1) + "\n";
    } else {
        char header[512];
        std::snprintf(header, sizeof header, "# %s, %s shader, LP_NUM_THREADS=%s, median of %d frames after %d warm-up, glFinish each\n",
                      description.c_str(), args.instrumented ? "instrumented" : "runtime (plain sprite)", lp_threads ? lp_threads : "",
                      args.frames, args.warmup);
        if (args.instrumented) {
            text = header + table(results);
            text += "# Obj: draw calls; Tri: triangles; OD: fragments passing the depth test (GL_SAMPLES_PASSED) / all viewport pixels\n"
                    "#   (empty pixels count 0, so OD < 1 when the scene leaves pixels uncovered);\n"
                    "# covered: share of viewport pixels showing a non-transparent texel;\n"
                    "# ideal: per pixel, elements with a visible texel down to the first fully opaque one;\n"
                    "# ms, min ms: median and fastest frame (modes take turns frame by frame);\n"
                    "# maxdiff, diffpx: largest RGBA channel difference and pixels that differ from the overpaint frame\n"
                    "#   (both drawn with 1/64 px coverage skirts and the rect test; with nearest filtering both must be 0);\n"
                    "# offedge: of those, pixels farther than 1/64 px from every triangle edge and texel edge (rounding cannot explain them).\n";
        } else {
            text = header + runtime_table(results);
            // Only scenes planned for the target have predictions (past
            // kMaxTargetElements a scene is planned without it).
            const auto planned = std::find_if(results.begin(), results.end(), [](const SceneResult& r) { return !r.target.empty(); });
            if (!args.input.target.empty() && planned != results.end()) {
                char line[256];
                std::snprintf(line, sizeof line, "# --target %s: pred ms is the cost model's prediction (docs/cost-model.md); error against cpu ms; median |error| %.1f%%\n",
                              planned->target.c_str(), 100 * median_prediction_error(results));
                text += line;
            }
            text += "# Obj: draw calls; Tri: triangles; raster: fragments rasterized with the depth test off / viewport pixels;\n"
                    "# OD: fragments shaded (passing the depth test, GL_SAMPLES_PASSED) / all viewport pixels\n"
                    "#   (empty pixels count 0, so OD < 1 when the scene leaves pixels uncovered);\n"
                    "# covered: share of viewport pixels showing a non-transparent texel;\n"
                    "# ideal: per pixel, elements with a visible texel down to the first fully opaque one;\n"
                    "# ms, cpu ms: median wall and process CPU time per frame (modes take turns frame by frame);\n"
                    "# diffpx: pixels that differ from the runtime's overpaint frame; offedge: of those, pixels whose centre\n"
                    "#   is on no texel edge (with nearest filtering it must be 0).\n";
        }
    }
    return text;
}

void run_bench(BenchArgs& args) {
    if (args.sprites > 0 || args.bunnymark > 0)
        return run_sprite_bench({args.scenes, args.sprites, args.bunnymark, args.frames_option->count() ? args.frames : 60, args.seed,
                                 args.json_output, args.output, args.quiet, args.lp_threads, &args.input});
    const std::vector<render::Mode> modes = parse_modes(args.modes);
    args.instrumented = args.shader == BenchArgs::Shader::instrumented;
    const char* lp_threads = pin_lp_threads(args.lp_threads);

    // Checked first, committed together at the end: a failure writes none.
    RunOutputs outputs(args.scenes);
    outputs.add_inputs(target_inputs(args.input.target));
    outputs.add(args.output);
    outputs.add(args.report);
    args.opaque_given = args.input.opaque;
    std::unique_ptr<render::GlRenderer> renderer;
    std::unique_ptr<render::GlHost> host;
    std::string description;
    if (args.instrumented) {
        renderer = open_renderer(args.input);
        description = renderer->description();
    } else {
        host = open_host(args.input.platform);
        description = host->description();
    }
    const char* command = args.report_only ? "report" : "bench";
    std::vector<SceneResult> results;
    report::RunReport run;
    Progress progress(command, "scenes", args.scenes.size(), args.quiet);
    for (const std::string& path : args.scenes) {
        results.push_back(bench_scene(path, args, modes, renderer.get(), host.get(), progress, outputs, run));
        progress.add();
    }
    progress.finish();
    if (!args.report.empty()) {
        run.title = args.scenes.size() == 1 ? "depthcull report: " + args.scenes.front() : "depthcull report: " + std::to_string(args.scenes.size()) + " scenes";
        run.command = g_command_line;
        run.renderer = description;
        run.options = report_options(args.input, args.frames, args.warmup, args.instrumented ? "instrumented (render --compare's)" : "runtime (plain sprite, depthcull::runtime)");
        outputs.stage(args.report, report::report_html(run));
    }
    const auto report_written = [&] {
        if (!args.report.empty() && !args.quiet)
            std::fprintf(stderr, "depthcull: %s: report of %zu scene%s written to %s\n", command, args.scenes.size(),
                         args.scenes.size() == 1 ? "" : "s", args.report.c_str());
    };
    if (args.report_only) {
        outputs.commit();
        return report_written();
    }

    const std::string text = bench_text(results, description, args, lp_threads);
    outputs.stage(args.output.empty() ? "-" : args.output, text);
    outputs.commit();
    report_written();
}

} // namespace

void add_bench_command(CLI::App& app) {
    auto args = std::make_shared<BenchArgs>();
    auto* cmd = app.add_subcommand("bench", "Table 2: draw calls, triangles, overdraw and ms per frame, measured by drawing");
    cmd->add_option("scenes", args->scenes, "Scenes: .json (our format) or .tmx / .tmx.gz (Tiled)")->required();
    args->frames_option = cmd->add_option("--frames", args->frames, "Timed frames per scene and mode (median reported; 0: no timing; "
                                                                    "--sprites / --bunnymark: frames drawn, default 60)")
                              ->check(CLI::Range(0, 100000))
                              ->capture_default_str();
    cmd->add_option("--sprites", args->sprites,
                    "N moving sprites of the scene's own pictures in its game layer (first insertion point: a Tiled map's first object "
                    "layer), every frame: plain batching, meshes only, depth-culled")
        ->check(CLI::Range(1, 1000000));
    cmd->add_option("--bunnymark", args->bunnymark, "N sprites of the scene's pictures bouncing alone (no static scene), every frame as --sprites")
        ->check(CLI::Range(1, 1000000));
    cmd->add_option("--seed", args->seed, "--sprites / --bunnymark: the seed of positions, rotations, scales, animation frames")->capture_default_str();
    cmd->add_option("--warmup", args->warmup, "Untimed frames before timing")->check(CLI::Range(0, 10000))->capture_default_str();
    cmd->add_option("--modes", args->modes, "Comma-separated: overpaint, meshes, optimized")->capture_default_str();
    cmd->add_option("--lp-threads", args->lp_threads, "LP_NUM_THREADS for llvmpipe (default: the environment's, else 1)")
        ->check(CLI::Range(0, 64));
    cmd->add_flag("--json", args->json_output, "JSON instead of the table");
    cmd->add_option("--renderer", args->shader,
                    "runtime: depthcull::runtime, the plain sprite shader an engine runs (default); "
                    "instrumented: the measuring renderer of render --compare")
        ->transform(choice<BenchArgs::Shader>({{"runtime", BenchArgs::Shader::runtime}, {"instrumented", BenchArgs::Shader::instrumented}}))
        ->default_str("runtime");
    cmd->add_option("-o,--output", args->output, "Write the table / JSON here (atomically) instead of stdout");
    cmd->add_option("--report", args->report, "Also write the HTML report of the run here (as depthcull report)")->type_name("FILE.html");
    add_quiet_flag(*cmd, args->quiet);
    add_render_input_options(*cmd, args->input);
    cmd->callback([args] { run_bench(*args); });
}

void add_report_command(CLI::App& app) {
    auto args = std::make_shared<BenchArgs>();
    args->report_only = true;
    args->frames = 10;
    args->warmup = 2;
    auto* cmd = app.add_subcommand("report", "One self-contained HTML page per run: Table 2, frames, heatmaps, per-image polygons");
    cmd->add_option("scenes", args->scenes, "Scenes: .json (our format) or .tmx / .tmx.gz (Tiled)")->required();
    cmd->add_option("-o,--output", args->report, "The HTML file to write")->required()->type_name("FILE.html");
    cmd->add_option("--frames", args->frames, "Timed frames per scene and mode (median reported; 0: no timing)")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    cmd->add_option("--warmup", args->warmup, "Untimed frames before timing")->check(CLI::Range(0, 10000))->capture_default_str();
    cmd->add_option("--lp-threads", args->lp_threads, "LP_NUM_THREADS for llvmpipe (default: the environment's, else 1)")
        ->check(CLI::Range(0, 64));
    cmd->add_option("--renderer", args->shader,
                    "runtime: depthcull::runtime, the plain sprite shader an engine runs (default); "
                    "instrumented: the measuring renderer of render --compare")
        ->transform(choice<BenchArgs::Shader>({{"runtime", BenchArgs::Shader::runtime}, {"instrumented", BenchArgs::Shader::instrumented}}))
        ->default_str("runtime");
    add_quiet_flag(*cmd, args->quiet);
    add_render_input_options(*cmd, args->input);
    cmd->callback([args] { run_bench(*args); });
}

#else

void add_bench_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("bench", "Table 2 measured by drawing (not in this build)");
    cmd->allow_extras();
    cmd->callback([] { throw CliError("bench: this depthcull was built without the renderer (DEPTHCULL_BUILD_RENDER=OFF)"); });
}

void add_report_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("report", "HTML report of a run (not in this build)");
    cmd->allow_extras();
    cmd->callback([] { throw CliError("report: this depthcull was built without the renderer (DEPTHCULL_BUILD_RENDER=OFF)"); });
}

#endif

} // namespace depthcull::cli
