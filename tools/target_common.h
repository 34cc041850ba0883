// --target PROFILE (issue 14) for optimize, render, bench and analyze:
// the option (pipeline::optimize plans for it).
#pragma once

#include <memory>
#include <string>

#include "cli.h"
#include "depthcull/pipeline.h"
#include "depthcull/target.h"

namespace depthcull::cli {

// --target NAME|FILE.json
void add_target_option(CLI::App& command, std::string& target);

} // namespace depthcull::cli
