// --target PROFILE (issue 14) for optimize, render, bench and analyze:
// the choices of choose_for_target applied to a prepared scene.
#pragma once

#include <memory>
#include <string>

#include "cli.h"
#include "depthcull/pipeline.h"
#include "depthcull/target.h"

namespace depthcull::cli {

// --target NAME|FILE.json
void add_target_option(CLI::App& command, std::string& target);

// Plans the scene for the target (nothing when `target` is empty): replaces
// prepared.analysis with the chosen analyses (a value: the plan returned
// is only the record of the choice) and sets reconstruct->opaque_polygons
// as chosen. Prints one line of what was
// chosen on stderr unless quiet.
std::unique_ptr<pipeline::TargetPlan> apply_target(const std::string& target, const std::string& path, pipeline::PreparedScene& prepared,
                                             const pipeline::PrepareOptions& prepare, ReconstructOptions* reconstruct, bool quiet);

#ifdef DEPTHCULL_HAVE_RENDER
struct RenderInput;
// apply_target for render, bench and report: the prepare options of
// prepare_for_render, and input.opaque set as chosen.
std::unique_ptr<pipeline::TargetPlan> apply_render_target(const std::string& path, pipeline::PreparedScene& prepared, RenderInput& input, bool quiet);
#endif

} // namespace depthcull::cli
