// STUB: depthcull import (see the issues).
#include "cli.h"

namespace depthcull::cli {

void add_import_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("import", "(not implemented yet)");
    cmd->callback([] { throw CliError("import: not implemented yet"); });
}

} // namespace depthcull::cli
