#include "target_common.h"

#include <cstdio>

namespace depthcull::cli {

void add_target_option(CLI::App& cmd, std::string& target) {
    cmd.add_option("--target", target,
                   "Optimize for this renderer: a built-in profile (llvmpipe, ipad1) or a profile JSON from `depthcull calibrate` "
                   "(vertex budget, opaque polygons and hidden elements chosen for the lowest predicted frame time)")
        ->type_name("PROFILE");
}

void add_target_stage_options(CLI::App& cmd, pipeline::PrepareOptions& prepare) {
    cmd.add_flag("!--no-clip-hidden", prepare.clip_hidden,
                 "With --target: do not clip hidden parts away at the opaque polygons in front (docs/ideal-frame.md)");
    cmd.add_flag("!--no-merge-opaque", prepare.merge_opaque,
                 "With --target: do not merge opaque tiles laid out as in their image into blocks (docs/ideal-frame.md)");
}

std::unique_ptr<pipeline::TargetPlan> apply_target(const std::string& target, const std::string& path, pipeline::PreparedScene& prepared,
                                             const pipeline::PrepareOptions& prepare, ReconstructOptions* reconstruct, bool quiet) {
    if (target.empty()) return nullptr;
    auto plan = std::make_unique<pipeline::TargetPlan>(pipeline::apply_target(prepared, prepare, pipeline::resolve_target(target), *reconstruct));
    if (!quiet) std::fprintf(stderr, "depthcull: %s\n", pipeline::target_summary(path, *plan).c_str());
    return plan;
}

} // namespace depthcull::cli
