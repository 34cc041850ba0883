// --target PROFILE (issue 14) for optimize, render, bench and analyze:
// the option (pipeline::optimize plans for it).
#pragma once

#include <memory>
#include <string>

#include "cli.h"
#include "depthcull/pipeline.h"
#include "depthcull/target.h"

namespace depthcull::cli {

// The profile --target names: resolve_target's, or for "auto" the GL
// renderer's (pipeline::auto_profile: built in, else calibrated once and
// cached in pipeline::default_profile_cache_dir()), with one line on
// stderr unless quiet. Without GL: a CliError saying what to give instead.
CostProfile resolve_cli_target(const std::string& target, bool quiet);

// --target NAME|FILE.json
void add_target_option(CLI::App& command, std::string& target);
// The profile file --target reads, as an input no output may replace; none
// for a built-in profile, auto or no target.
std::vector<std::string> target_inputs(const std::string& target);
// --no-clip-hidden, --no-merge-opaque: issue 25's stages of --target off
// (PrepareOptions::clip_hidden, merge_opaque), to measure each alone.
void add_target_stage_options(CLI::App& command, pipeline::PrepareOptions& prepare);

} // namespace depthcull::cli
