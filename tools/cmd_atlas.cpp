// depthcull atlas SHEET.json -o OUT.json: a TexturePacker atlas written back
// with our boundary polygons in TexturePacker's polygon fields (vertices,
// verticesUV, triangles), for engines that draw polygon sprites.
#include <cstdio>

#include "cli.h"

namespace depthcull::cli {

namespace {

struct AtlasArgs {
    std::string input;
    std::string output;
    AnalyzeOptions analyze;
};

void run_atlas(const AtlasArgs& args) {
    check_distinct_files({args.input, io::load_texturepacker(args.input).image_path}, {args.output});
    io::AtlasPolygonStats stats;
    std::string text = io::atlas_with_polygons(args.input, args.analyze, &stats);
    write_output(args.output, text);
    // The analyzer's figure: area the engine fills, polygons vs whole frames.
    std::fprintf(stderr, "%s: %d frames, %lld vertices, %lld triangles, polygon area %.0f of %.0f frame texels (%.1f%%)\n",
                 args.input.c_str(), stats.frames, static_cast<long long>(stats.vertices), static_cast<long long>(stats.triangles),
                 stats.polygon_area, stats.frame_area, stats.frame_area > 0 ? 100.0 * stats.polygon_area / stats.frame_area : 0.0);
}

} // namespace

void add_atlas_command(CLI::App& app) {
    auto args = std::make_shared<AtlasArgs>();
    auto* cmd = app.add_subcommand("atlas", "Add boundary polygons to a TexturePacker JSON atlas (vertices, verticesUV, triangles)");
    cmd->add_option("atlas", args->input, "TexturePacker JSON (hash or array form)")->required();
    cmd->add_option("-o,--output", args->output, "Atlas JSON to write (default: stdout)");
    add_boundary_options(*cmd, args->analyze.boundary);
    cmd->callback([args] { run_atlas(*args); });
}

} // namespace depthcull::cli
