// depthcull: depth-cull optimization of 2D scenes for 3D graphics hardware.
#include <cstdio>
#include <exception>

#include "cli.h"
#include "depthcull/io.h"

int main(int argc, char** argv) {
    CLI::App app{"depthcull: depth-cull optimization of 2D scenes for 3D graphics hardware"};
    app.name("depthcull");
    app.require_subcommand(1);
    app.set_version_flag("--version", "depthcull 0.1.0");
    depthcull::cli::add_analyze_command(app);
    depthcull::cli::add_optimize_command(app);
    depthcull::cli::add_render_command(app);
    depthcull::cli::add_bench_command(app);
    depthcull::cli::add_import_command(app);
    depthcull::cli::add_atlas_command(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "depthcull: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
