#include "target_common.h"

#include <cstdio>

#ifdef DEPTHCULL_HAVE_RENDER
#include "render_common.h"
#endif

namespace depthcull::cli {

void add_target_option(CLI::App& cmd, std::string& target) {
    cmd.add_option("--target", target,
                   "Optimize for this renderer: a built-in profile (llvmpipe, ipad1) or a profile JSON from `depthcull calibrate` "
                   "(vertex budget, opaque polygons and hidden elements chosen for the lowest predicted frame time)")
        ->type_name("PROFILE");
}

std::unique_ptr<pipeline::TargetPlan> apply_target(const std::string& target, const std::string& path, pipeline::PreparedScene& prepared,
                                             const pipeline::PrepareOptions& prepare, ReconstructOptions* reconstruct, bool quiet) {
    if (target.empty()) return nullptr;
    const CostProfile profile = io::resolve_target(target);
    auto plan = std::make_unique<pipeline::TargetPlan>(pipeline::plan_target(prepared, prepare, profile, *reconstruct));
    prepared.analysis = plan->analysis;
    *reconstruct = plan->reconstruct;
    if (!quiet) {
        const TargetChoice& c = plan->choice;
        std::fprintf(stderr,
                     "depthcull: %s: --target %s: predicted %.3f ms (overpaint %.3f, meshes only %.3f); opaque pass %s, %lld elements with "
                     "opaque polygons (%lld given up per element), %lld hidden elements dropped, MIN_OPAQUE_AREA %d%s%s\n",
                     path.c_str(), profile.name.c_str(), c.predicted_ms, c.overpaint_ms, c.meshes_only_ms, c.opaque_pass ? "on" : "off",
                     (long long)c.elements_opaque, (long long)c.elements_reverted, (long long)c.elements_dropped, plan->min_opaque_area, c.fallback.empty() ? "" : "; fallback: ",
                     c.fallback.c_str());
    }
    return plan;
}

#ifdef DEPTHCULL_HAVE_RENDER
std::unique_ptr<pipeline::TargetPlan> apply_render_target(const std::string& path, pipeline::PreparedScene& prepared, RenderInput& in, bool quiet) {
    if (in.target.empty()) return nullptr;
    const pipeline::PrepareOptions prepare = prepare_options(in); // as prepare_for_render prepared it
    ReconstructOptions reconstruct = reconstruct_options(in);
    auto plan = apply_target(in.target, path, prepared, prepare, &reconstruct, quiet);
    in.opaque = reconstruct.opaque_polygons;
    in.reconstruct.clip_hidden = reconstruct.clip_hidden;
    in.reconstruct.merge_opaque = reconstruct.merge_opaque;
    return plan;
}
#endif

} // namespace depthcull::cli
