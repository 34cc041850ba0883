// STUB: depthcull bench (see the issues).
#include "cli.h"

namespace depthcull::cli {

void add_bench_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("bench", "(not implemented yet)");
    cmd->callback([] { throw CliError("bench: not implemented yet"); });
}

} // namespace depthcull::cli
