// --target PROFILE (issue 14) for optimize, render, bench and analyze:
// the option, and pipeline::apply_target with its one line on stderr.
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
// --no-clip-hidden, --no-merge-opaque: issue 25's stages of --target off
// (PrepareOptions::clip_hidden, merge_opaque), to measure each alone.
void add_target_stage_options(CLI::App& command, pipeline::PrepareOptions& prepare);

// pipeline::apply_target for `target` (nothing when it is empty): prepared
// and *reconstruct get the choice. Prints pipeline::target_summary on
// stderr unless quiet.
std::unique_ptr<pipeline::TargetPlan> apply_target(const std::string& target, const std::string& path, pipeline::PreparedScene& prepared,
                                             const pipeline::PrepareOptions& prepare, ReconstructOptions* reconstruct, bool quiet);

} // namespace depthcull::cli
