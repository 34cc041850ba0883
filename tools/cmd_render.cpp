// STUB: depthcull render (see the issues).
#include "cli.h"

namespace depthcull::cli {

void add_render_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("render", "(not implemented yet)");
    cmd->callback([] { throw CliError("render: not implemented yet"); });
}

} // namespace depthcull::cli
