// depthcull import MAP.tmx -o SCENE.json [--viewport x,y,w,h]: a Tiled map
// (.tmx, .tmx.gz) as our scene JSON, so an asset build can check it in or
// edit it; optimize, render and bench also read maps directly.
#include <cstdio>

#include "cli.h"

namespace depthcull::cli {

namespace {

struct ImportArgs {
    std::string input;
    std::string output;
    io::LoadOptions load;
};

void run_import(const ImportArgs& args) {
    check_distinct_files({args.input}, {args.output});
    io::LoadOptions load = args.load;
    std::vector<std::string> documents;
    load.documents = &documents;
    Scene scene = io::read_scene(args.input, load);
    check_distinct_files(scene_inputs(args.input, scene, documents), {args.output});
    write_output(args.output, io::scene_to_json_text(scene, args.output));
    const Viewport& v = scene.viewport;
    std::fprintf(stderr, "%s: %zu elements, %zu images, viewport %g,%g,%d,%d\n", args.input.c_str(), scene.elements.size(),
                 scene.images.size(), v.x, v.y, v.width, v.height);
}

} // namespace

void add_import_command(CLI::App& app) {
    auto args = std::make_shared<ImportArgs>();
    auto* cmd = app.add_subcommand("import", "Convert a Tiled map (.tmx, .tmx.gz) to scene JSON");
    cmd->add_option("map", args->input, "Tiled map (.tmx or .tmx.gz; a scene .json is rewritten)")->required();
    cmd->add_option("-o,--output", args->output, "Scene JSON to write (default: stdout)");
    add_viewport_option(*cmd, args->load);
    cmd->callback([args] { run_import(*args); });
}

} // namespace depthcull::cli
