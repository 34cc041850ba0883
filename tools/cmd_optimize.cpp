// STUB: depthcull optimize (see the issues).
#include "cli.h"

namespace depthcull::cli {

void add_optimize_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("optimize", "(not implemented yet)");
    cmd->callback([] { throw CliError("optimize: not implemented yet"); });
}

} // namespace depthcull::cli
