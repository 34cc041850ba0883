// depthcull optimize: scene -> optimized meshes (paper 2.3), with the
// before/after figures against overpaint (Table 2's columns).
#include <cinttypes>
#include <cstdio>
#include <map>

#include "cli.h"
#include "target_common.h"
#include "depthcull/io.h"
#include "depthcull/scene.h"
#include "progress.h"

namespace depthcull::cli {

namespace {

struct OptimizeArgs {
    std::string scene;
    std::string output;
    std::string binary;
    std::string cache_dir;
    bool no_cache = false;
    io::PrepareOptions prepare;
    ReconstructOptions reconstruct;
    bool opaque = true;
    bool stats = false;
    bool timing = true;
    bool quiet = false;
    CLI::Option* filter_option = nullptr;
    std::string target;
};

std::string figures(const io::PreparedScene& p, const SceneMeshes& overpaint, const SceneMeshes& rects, const SceneMeshes& optimized) {
    const SceneStats& o = overpaint.stats;
    const SceneStats& r = rects.stats;
    const SceneStats& s = optimized.stats;
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "%-13s %12s %12s %12s\n"
                  "%-13s %12" PRId64 " %12" PRId64 " %12" PRId64 "\n"
                  "%-13s %12" PRId64 " %12" PRId64 " %12" PRId64 "\n"
                  "%-13s %12s %12s %12" PRId64 "\n"
                  "graph edges %" PRId64 ", depth buffer bits needed %" PRId64 "\n"
                  "images analyzed %d, from cache %d, analysis %.3f s, reconstruction %.3f s\n",
                  "", "overpaint", "meshes only", "optimized", "draw calls", o.draw_calls, r.draw_calls, s.draw_calls, "triangles",
                  o.triangles, r.triangles, s.triangles, "depth levels", "-", "-", s.depth_levels, s.graph_edges, s.depth_bits,
                  p.analyzed, p.cache_hits, p.analysis_seconds, s.seconds);
    return buf;
}

void run_optimize(OptimizeArgs& args) {
    io::PrepareOptions prepare = args.prepare;
    prepare.analyze.opaque.filter = prepare.analyze.boundary.filter;
    prepare.filter_from_scene = args.filter_option->count() == 0;
    if (!args.no_cache) prepare.cache_dir = args.cache_dir.empty() ? io::default_cache_dir() : args.cache_dir;
    check_distinct_files({args.scene}, {args.output, args.binary});
    io::PreparedScene prepared;
    {
        Progress progress("optimize", "images analyzed", 0, args.quiet);
        prepare.progress = [&progress](std::size_t done, std::size_t total) { progress.set(done, total); };
        prepared = io::prepare_scene(args.scene, prepare);
    }
    check_distinct_files(scene_inputs(args.scene, prepared.scene), {args.output, args.binary});

    if (args.reconstruct.sort == SortMethod::paper && prepared.scene.elements.size() > kPaperSortMaxElements)
        std::fprintf(stderr, "depthcull: warning: --sort paper is quadratic (paper 2.3.1); %zu elements may take long\n",
                     prepared.scene.elements.size());
    ReconstructOptions options = args.reconstruct;
    options.opaque_polygons = args.opaque;
    prepare.progress = nullptr;
    const auto plan = apply_target(args.target, args.scene, prepared, prepare, &options, args.quiet);
    SceneMeshes meshes;
    switch (reconstruct_scene(prepared.scene, prepared.element_analysis, options, &meshes)) {
    case ReconstructStatus::ok: break;
    case ReconstructStatus::invalid_scene: throw CliError(args.scene + ": invalid scene for reconstruction");
    case ReconstructStatus::too_many_depth_levels:
        throw CliError(args.scene + ": more than " + std::to_string(kMaxDepthLevels) +
                       " depth levels (overlap chains too long for a 24-bit depth buffer)");
    }
    if (meshes.stats.depth_bits > 16)
        std::fprintf(stderr, "depthcull: warning: %s: %" PRId64 " depth levels need a 24-bit depth buffer (16-bit holds %" PRId64 ")\n",
                     args.scene.c_str(), meshes.stats.depth_levels, kMaxDepthLevels16);

    if (!args.binary.empty()) {
        io::write_meshes_binary(args.binary, prepared.scene, meshes, args.timing);
        if (!prepared.scene.animations.empty())
            std::fprintf(stderr, "warning: %s: binary meshes do not carry the scene's %zu animations (the JSON meshes do: -o)\n",
                         args.binary.c_str(), prepared.scene.animations.size());
    }
    // No -o on a terminal: 100 KB of JSON on the screen helps nobody; say
    // where it goes instead (-o - still prints it; a pipe gets it as before).
    const bool hold_back = args.output.empty() && args.binary.empty() && stdout_is_terminal();
    if (hold_back) {
        const std::size_t bytes = io::meshes_to_json(prepared.scene, meshes, "", args.timing).size();
        std::fprintf(stderr,
                     "depthcull: optimize: the meshes JSON (%zu KB) is not printed on a terminal: give -o MESHES.json and/or "
                     "--binary MESHES.bin to write it, -o - to print it, or pipe stdout\n",
                     (bytes + 1023) / 1024);
    } else if (!args.output.empty() || args.binary.empty()) {
        if (args.output.empty() || args.output == "-") write_output("", io::meshes_to_json(prepared.scene, meshes, "", args.timing));
        else io::write_meshes_json(args.output, prepared.scene, meshes, args.timing);
    }

    SceneMeshes overpaint = overpaint_meshes(prepared.scene);
    SceneMeshes rects;
    if (rectangle_meshes(prepared.scene, options, &rects) != ReconstructStatus::ok) rects = overpaint;
    std::string text = figures(prepared, overpaint, rects, meshes);
    if (args.stats) {
        bool json_on_stdout = !hold_back && args.binary.empty() && (args.output.empty() || args.output == "-");
        std::fputs(text.c_str(), json_on_stdout ? stderr : stdout);
    } else if (!args.quiet) {
        std::fprintf(stderr, "depthcull: %s: draw calls %" PRId64 " -> %" PRId64 ", triangles %" PRId64 " -> %" PRId64 ", depth levels %" PRId64 "\n",
                     args.scene.c_str(), overpaint.stats.draw_calls, meshes.stats.draw_calls, overpaint.stats.triangles,
                     meshes.stats.triangles, meshes.stats.depth_levels);
    }
}

} // namespace

void add_optimize_command(CLI::App& app) {
    auto args = std::make_shared<OptimizeArgs>();
    auto* cmd = app.add_subcommand("optimize", "Reconstruct a scene into depth-tested meshes (paper 2.3)");
    cmd->add_option("scene", args->scene, "Scene: .json (our format) or .tmx / .tmx.gz (Tiled)")->required();
    cmd->add_option("-o,--output", args->output, "Meshes JSON (docs/mesh-format.md); '-' or nothing: stdout");
    cmd->add_option("--binary", args->binary, "Also (or only) write the binary meshes form here");
    cmd->add_option("--cache", args->cache_dir, "Analysis cache directory (default: $XDG_CACHE_HOME/depthcull/analysis or ~/.cache/depthcull/analysis)");
    cmd->add_flag("--no-cache", args->no_cache, "Analyze every image, read and write no cache");
    add_reconstruct_options(*cmd, args->reconstruct);
    add_target_option(*cmd, args->target);
    cmd->add_flag("!--no-opaque", args->opaque, "No opaque pass: boundary polygons only");
    cmd->add_flag("--cull", args->reconstruct.cull_to_viewport,
                  "Drop elements entirely outside the viewport (meshes for that one camera position)");
    cmd->add_option("--reserve-dynamic", args->reconstruct.reserved_dynamic_levels,
                    "Depth levels to keep free in front of the scene for dynamic elements")
        ->check(CLI::Range(std::int64_t(0), kMaxDepthLevels));
    add_viewport_option(*cmd, args->prepare.load);
    add_analysis_options(*cmd, args->prepare.analyze);
    args->filter_option = cmd->get_option("--filter");
    cmd->add_option("-j,--threads", args->prepare.threads, "Worker threads for the analysis (0: all cores); output never depends on it")
        ->capture_default_str();
    cmd->add_flag("--stats", args->stats, "Print draw calls, triangles and depth levels: overpaint, meshes only, optimized");
    cmd->add_flag("!--no-timing", args->timing, "Write 0 for seconds, for byte-identical output across runs");
    add_quiet_flag(*cmd, args->quiet);
    cmd->callback([args] { run_optimize(*args); });
}

} // namespace depthcull::cli
