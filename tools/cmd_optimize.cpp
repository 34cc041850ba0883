// depthcull optimize: scene -> optimized meshes (paper 2.3), with the
// before/after figures against overpaint (Table 2's columns).
#include <cinttypes>
#include <cstdio>
#include <map>

#include "cli.h"
#include "target_common.h"
#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "depthcull/overdraw.h"
#include "depthcull/scene.h"
#include "outputs.h"
#include "progress.h"

namespace depthcull::cli {

namespace {

struct OptimizeArgs {
    std::string scene;
    std::string output;
    std::string binary;
    CacheChoice cache;
    pipeline::PrepareOptions prepare;
    ReconstructOptions reconstruct;
    bool opaque = true;
    bool stats = false;
    bool timing = true;
    bool quiet = false;
    std::string target;
    std::int64_t insertion_levels = -1; // --insertion-levels; -1: not given
};

// The overdraw rows of --stats (depthcull/overdraw.h, no GL): fragments over
// the scene's viewport for overpaint and the optimized meshes, and the ideal.
struct OverdrawFigures {
    OverdrawStats overpaint, optimized, ideal;
};

OverdrawFigures overdraw_figures(const pipeline::PreparedScene& p, const SceneMeshes& optimized) {
    OverdrawFigures f;
    f.overpaint = analyze_overdraw(overpaint_meshes(p.scene));
    f.optimized = analyze_overdraw(optimized);
    f.ideal = ideal_overdraw(p.scene, p.views());
    return f;
}

// Wall times of optimize's two stages, measured here (not in the values).
struct StageSeconds {
    double analysis = 0, reconstruction = 0;
};

std::string figures(const pipeline::PreparedScene& p, const SceneStats& o, const SceneStats& r, const SceneStats& s,
                    const OverdrawFigures* od, const StageSeconds& seconds) {
    char buf[2048];
    int n = std::snprintf(buf, sizeof buf,
                          "%-20s %12s %12s %12s\n"
                          "%-20s %12" PRId64 " %12" PRId64 " %12" PRId64 "\n"
                          "%-20s %12" PRId64 " %12" PRId64 " %12" PRId64 "\n"
                          "%-20s %12s %12s %12" PRId64 "\n",
                          "", "overpaint", "meshes only", "optimized", "draw calls", o.draw_calls, r.draw_calls, s.draw_calls,
                          "triangles", o.triangles, r.triangles, s.triangles, "depth levels", "-", "-", s.depth_levels);
    if (od) {
        // Meshes only draws overpaint's rects (the same float vertices and
        // quads) in another order without a depth test, so it rasterizes
        // and shades exactly what overpaint does.
        n += std::snprintf(buf + n, sizeof buf - std::size_t(n),
                           "%-20s %12" PRId64 " %12" PRId64 " %12" PRId64 "\n"
                           "%-20s %12" PRId64 " %12" PRId64 " %12" PRId64 "\n"
                           "%-20s %12.3f %12.3f %12.3f\n"
                           "ideal overdraw %.3f (%" PRId64 " fragments) over %" PRId64 " viewport pixels\n",
                           "fragments rasterized", od->overpaint.rasterized, od->overpaint.rasterized, od->optimized.rasterized,
                           "fragments shaded", od->overpaint.shaded, od->overpaint.shaded, od->optimized.shaded, "overdraw",
                           od->overpaint.overdraw(), od->overpaint.overdraw(), od->optimized.overdraw(), od->ideal.overdraw(),
                           od->ideal.shaded, od->ideal.pixels);
    }
    std::snprintf(buf + n, sizeof buf - std::size_t(n),
                  "graph edges %" PRId64 ", depth buffer bits needed %" PRId64 "\n"
                  "images analyzed %d, from cache %d, analysis %.3f s, reconstruction %.3f s\n",
                  s.graph_edges, s.depth_bits, p.analyzed, p.cache_hits, seconds.analysis, seconds.reconstruction);
    return buf;
}

// Step 1: what pipeline::optimize is asked for.
pipeline::OptimizeOptions options_from_args(const OptimizeArgs& args) {
    pipeline::OptimizeOptions o;
    o.prepare = args.prepare;
    // No opaque pass: skip the opaque search rather than compute and drop it.
    if (!args.opaque) o.prepare.analyze.opaque.max_polygons = 0;
    o.prepare.cache_dir = args.cache.directory();
    o.reconstruct = args.reconstruct;
    o.reconstruct.opaque_polygons = args.opaque;
    o.target = args.target;
    if (!args.target.empty()) o.profile = resolve_cli_target(args.target, args.quiet); // --target auto finds the GL renderer here
    // Depth ranges for moving sprites at the scene's insertion points
    // (object layers, the scene JSON's, --insert-at), written into the files.
    o.insertion_levels = args.insertion_levels >= 0 ? args.insertion_levels : args.prepare.load.insert_at.empty() ? 0 : 1024;
    return o;
}

// Where the meshes go: the JSON (to json_path, "-" for stdout), held back
// (no -o on a terminal), and/or the binary form.
struct MeshOutputs {
    bool hold_back = false;
    bool json = false;
    std::string json_path;
};

// Step 2: the outputs, checked before the analysis, staged and committed
// together at the end: a failure writes neither file.
MeshOutputs declare_outputs(const OptimizeArgs& args, RunOutputs& outputs) {
    MeshOutputs where;
    where.hold_back = args.output.empty() && args.binary.empty() && stdout_is_terminal();
    where.json = !where.hold_back && (!args.output.empty() || args.binary.empty());
    where.json_path = args.output.empty() ? "-" : args.output;
    if (where.json) outputs.add(where.json_path);
    outputs.add(args.binary);
    return where;
}

// Step 3: the pipeline, with the images analyzed as progress.
pipeline::OptimizeResult optimize_with_progress(const OptimizeArgs& args, pipeline::OptimizeOptions o) {
    Progress progress("optimize", "images analyzed", 0, args.quiet);
    o.prepare.progress = [&progress](std::size_t done, std::size_t total) { progress.set(done, total); };
    return pipeline::optimize(args.scene, o);
}

// Step 4: warnings about the run, and the reconstruction's status as an error.
void check_reconstruction(const OptimizeArgs& args, std::int64_t insertion_levels, const pipeline::OptimizeResult& result) {
    const pipeline::PreparedScene& prepared = result.prepared;
    const ReconstructOptions& options = result.reconstruct;
    if (args.reconstruct.sort == SortMethod::paper && prepared.scene.elements.size() > kPaperSortMaxElements)
        std::fprintf(stderr, "depthcull: warning: --sort paper is quadratic (paper 2.3.1); %zu elements may take long\n",
                     prepared.scene.elements.size());
    if (result.plan && !args.quiet) std::fprintf(stderr, "depthcull: %s\n", pipeline::target_summary(args.scene, *result.plan).c_str());
    if (insertion_levels > 0 && options.insertion_points.empty())
        std::fprintf(stderr, "depthcull: warning: %s: --insertion-levels: the scene has no insertion point (no object layer, no "
                             "\"insertion_points\", no --insert-at); the meshes reserve none\n", args.scene.c_str());
    switch (result.status) {
    case ReconstructStatus::ok: break;
    case ReconstructStatus::invalid_scene: throw CliError(args.scene + ": invalid scene for reconstruction");
    case ReconstructStatus::too_many_depth_levels:
        throw CliError(args.scene + ": more than " + std::to_string(kMaxDepthLevels) + " depth levels (overlap chains" +
                       (options.insertion_points.empty() ? "" : " and the insertion points' levels") + " too long for a 24-bit depth buffer)");
    }
    if (result.meshes.stats.depth_bits > 16)
        std::fprintf(stderr, "depthcull: warning: %s: %" PRId64 " depth levels need a 24-bit depth buffer (16-bit holds %" PRId64 ")\n",
                     args.scene.c_str(), result.meshes.stats.depth_levels, kMaxDepthLevels16);
}

// Step 5: the files, staged and committed together.
void write_meshes(const OptimizeArgs& args, const MeshOutputs& where, RunOutputs& outputs, const io::MeshesDocument& document) {
    if (!args.binary.empty())
        outputs.stage(args.binary, [&](const io::WriteBytes& write) { io::stream_meshes_binary(write, document, args.binary); });
    // No -o on a terminal: 100 KB of JSON on the screen helps nobody; say
    // where it goes instead (-o - still prints it; a pipe gets it as before).
    if (where.hold_back) {
        std::size_t bytes = 0; // counted as it is made, not built
        io::stream_meshes_json([&bytes](std::string_view piece) { bytes += piece.size(); }, document, "");
        std::fprintf(stderr,
                     "depthcull: optimize: the meshes JSON (%zu KB) is not printed on a terminal: give -o MESHES.json and/or "
                     "--binary MESHES.bin to write it, -o - to print it, or pipe stdout\n",
                     (bytes + 1023) / 1024);
    } else if (where.json) {
        // Streamed: a large scene's meshes JSON is never one string.
        const std::string path = args.output == "-" ? std::string() : args.output;
        outputs.stage(where.json_path, [&](const io::WriteBytes& write) { io::stream_meshes_json(write, document, path); });
    }
    outputs.commit();
}

// Step 6: before and after, as --stats' table or one line.
void print_figures(const OptimizeArgs& args, const MeshOutputs& where, const pipeline::PreparedScene& prepared,
                   const ReconstructOptions& options, const SceneMeshes& meshes, const StageSeconds& seconds) {
    // Counted, not built: the other columns' meshes are never drawn here.
    const SceneStats overpaint = overpaint_stats(prepared.scene);
    SceneStats rects;
    if (rectangle_stats(prepared.scene, options, &rects) != ReconstructStatus::ok) rects = overpaint;
    if (args.stats) {
        // Overdraw needs the viewport's pixels: a viewport past what render
        // draws (kMaxImageSide a side) is left out, as render refuses it.
        const Viewport& vp = prepared.scene.viewport;
        const bool overdraw = vp.width > 0 && vp.height > 0 && vp.width <= kMaxImageSide && vp.height <= kMaxImageSide;
        OverdrawFigures od;
        if (overdraw) od = overdraw_figures(prepared, meshes);
        const std::string text = figures(prepared, overpaint, rects, meshes.stats, overdraw ? &od : nullptr, seconds);
        bool json_on_stdout = !where.hold_back && args.binary.empty() && (args.output.empty() || args.output == "-");
        std::fputs(text.c_str(), json_on_stdout ? stderr : stdout);
    } else if (!args.quiet) {
        std::fprintf(stderr, "depthcull: %s: draw calls %" PRId64 " -> %" PRId64 ", triangles %" PRId64 " -> %" PRId64 ", depth levels %" PRId64 "\n",
                     args.scene.c_str(), overpaint.draw_calls, meshes.stats.draw_calls, overpaint.triangles,
                     meshes.stats.triangles, meshes.stats.depth_levels);
    }
}

void run_optimize(OptimizeArgs& args) {
    const pipeline::OptimizeOptions o = options_from_args(args);
    RunOutputs outputs({args.scene});
    outputs.add_inputs(target_inputs(args.target));
    const MeshOutputs where = declare_outputs(args, outputs);
    pipeline::OptimizeResult result = optimize_with_progress(args, o);
    outputs.add_inputs(scene_inputs(args.scene, result.prepared.scene, result.prepared.documents));
    check_reconstruction(args, o.insertion_levels, result);

    // The analysis figure counts the target's extra budgets too.
    const StageSeconds seconds{result.seconds.analysis + result.seconds.planning, result.seconds.reconstruction};
    // The files' document; stats.seconds is the reconstruction's wall time,
    // measured by the pipeline at its edge, or 0 (--no-timing): the writers
    // read no clock.
    io::MeshesDocument document = io::meshes_document(result.prepared.scene, std::move(result.meshes));
    if (args.timing) document.seconds = seconds.reconstruction;
    write_meshes(args, where, outputs, document);
    print_figures(args, where, result.prepared, result.reconstruct, document.meshes, seconds);
}

} // namespace

void add_optimize_command(CLI::App& app) {
    auto args = std::make_shared<OptimizeArgs>();
    auto* cmd = app.add_subcommand("optimize", "Reconstruct a scene into depth-tested meshes (paper 2.3)");
    cmd->add_option("scene", args->scene, "Scene: .json (our format) or .tmx / .tmx.gz (Tiled)")->required();
    cmd->add_option("-o,--output", args->output, "Meshes JSON (docs/mesh-format.md); '-' or nothing: stdout");
    cmd->add_option("--binary", args->binary, "Also (or only) write the binary meshes form here");
    add_cache_options(*cmd, args->cache);
    add_reconstruct_options(*cmd, args->reconstruct);
    add_target_option(*cmd, args->target);
    add_target_stage_options(*cmd, args->prepare);
    cmd->add_flag("!--no-opaque", args->opaque, "No opaque pass: boundary polygons only");
    cmd->add_flag("--cull", args->reconstruct.cull_to_viewport,
                  "Drop elements entirely outside the viewport (meshes for that one camera position)");
    cmd->add_option("--reserve-dynamic", args->reconstruct.reserved_dynamic_levels,
                    "Depth levels to keep free in front of the scene for dynamic elements")
        ->check(CLI::Range(std::int64_t(0), kMaxDepthLevels));
    cmd->add_option("--insert-at", args->prepare.load.insert_at,
                    "An insertion point for moving sprites (repeatable): a Tiled map's layer name (after its elements), a scene's "
                    "element index (before it); with every object layer and the scene JSON's insertion_points")
        ->type_name("LAYER|INDEX");
    cmd->add_option("--insertion-levels", args->insertion_levels,
                    "Depth levels (sprites per frame) reserved at each insertion point and written into the meshes; default "
                    "1024 with --insert-at, else 0 (no insertion points)")
        ->check(CLI::Range(std::int64_t(0), kMaxDepthLevels));
    add_viewport_option(*cmd, args->prepare.load);
    add_scene_analysis_options(*cmd, args->prepare);
    cmd->add_option("-j,--threads", args->prepare.threads, "Worker threads for the analysis (0: all cores); output never depends on it")
        ->capture_default_str();
    cmd->add_flag("--stats", args->stats, "Print draw calls, triangles, depth levels, fragments and overdraw: overpaint, meshes only, optimized (no GL)");
    cmd->add_flag("!--no-timing", args->timing, "Write 0 for seconds, for byte-identical output across runs");
    add_quiet_flag(*cmd, args->quiet);
    cmd->callback([args] { run_optimize(*args); });
}

} // namespace depthcull::cli
