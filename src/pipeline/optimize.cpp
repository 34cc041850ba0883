// pipeline::optimize: the one place the stages are strung together (load,
// settle, decode, analyze, plan for a target, reconstruct), and the one
// place they are timed. Every command that optimizes a scene, the C API and
// the examples call it, so a new stage is added here once.
#include <cstdint>
#include <string>
#include <utility>

#include "depthcull/target.h"
#include "pipeline/stages.h"
#include "pipeline/stopwatch.h"

namespace depthcull::pipeline {

namespace {

void announce(const OptimizeOptions& options, const char* stage) {
    if (options.stage) options.stage(stage);
}

// Plans for the target (when settled with one) and reconstructs: the
// stages after the analysis, shared by both sources.
void plan_and_reconstruct(const std::string& name, const OptimizeOptions& options, const Settled& settled, OptimizeResult& out) {
    PreparedScene& prepared = out.prepared;
    out.reconstruct = options.reconstruct;
    const std::size_t elements = prepared.scene.elements.size();
    if (settled.profile && elements > options.max_target_elements)
        io::report_warnings({name + ": " + std::to_string(elements) + " elements, more than the " + std::to_string(options.max_target_elements) +
                             " --target weighs (kMaxTargetElements): planned without a target (--viewport with --cull plans one camera's)"},
                            options.prepare.load);
    else if (settled.profile) {
        announce(options, "choosing for --target");
        const Stopwatch planning;
        // Sprites at insertion points and animations (element spans) need
        // the depth test: such meshes keep it, so the plan is made with it.
        PrepareOptions prepare = options.prepare;
        const bool points = options.insertion_levels > 0 && !prepared.scene.insertion_points.empty();
        prepare.depthless = prepare.depthless && !points && prepared.scene.animations.empty() && depthless_possible(out.reconstruct);
        out.plan = plan_target(prepared, prepare, *settled.profile, out.reconstruct);
        prepared.analysis = out.plan->choice.analysis;
        out.reconstruct = out.plan->reconstruct;
        out.seconds.planning = planning.seconds();
    }
    // Depth ranges for moving sprites at the scene's insertion points.
    const std::int64_t levels = options.insertion_levels;
    if (levels > 0) {
        for (std::size_t at : prepared.scene.insertion_points) out.reconstruct.insertion_points.push_back({at, levels});
        const std::size_t points = out.reconstruct.insertion_points.size();
        if (points > 0 && std::int64_t(points) > kMaxDepthLevels / levels)
            throw depthcull::Error(name + ": " + std::to_string(points) + " insertion points x " + std::to_string(levels) +
                            " levels (--insertion-levels) are more than the " + std::to_string(kMaxDepthLevels) +
                            " depth levels of a 24-bit depth buffer");
    }
    // The JSON meshes' "animated" vertex runs come from the element spans.
    out.reconstruct.element_spans = out.reconstruct.element_spans || !prepared.scene.animations.empty();
    if (!options.reconstruct_meshes) return;
    announce(options, "reconstructing");
    const Stopwatch reconstruction;
    out.status = reconstruct_scene(prepared.scene, prepared.analysis, out.reconstruct, &out.meshes);
    out.seconds.reconstruction = reconstruction.seconds();
}

} // namespace

Settled settle(const Scene& scene, const OptimizeOptions& options) {
    Settled s;
    s.filter = options.prepare.filter ? *options.prepare.filter : scene.filter;
    if (options.profile) s.profile = options.profile;
    else if (!options.target.empty()) s.profile = resolve_target(options.target);
    return s;
}

AnalyzeOptions analysis_options(const PrepareOptions& options, const Scene& scene) {
    AnalyzeOptions analyze = options.analyze;
    analyze.filter = scene.filter;
    return analyze;
}

OptimizeResult optimize(const std::string& path, const OptimizeOptions& options) {
    return io::guarded(path, [&] {
        OptimizeResult out;
        Settled settled;
        announce(options, "analyzing");
        const Stopwatch analysis;
        out.prepared = prepare_settled(path, options, &settled);
        out.seconds.analysis = analysis.seconds();
        plan_and_reconstruct(path, options, settled, out);
        return out;
    });
}

OptimizeResult optimize(SceneSource source, const OptimizeOptions& options) {
    OptimizeResult out;
    // A target given by name or already resolved (OptimizeOptions::profile).
    if (!options.target.empty() || options.profile)
        throw depthcull::Error("target " + (options.profile ? options.profile->name : options.target) +
                               ": planning needs the scene's pixels; optimize the scene file instead");
    const Settled settled = settle(source.scene, options);
    out.prepared.scene = std::move(source.scene);
    out.prepared.scene.filter = settled.filter;
    out.prepared.analysis = std::move(source.analysis);
    // No pixels: each image the one transparent texel PreparedScene::view gives.
    out.prepared.pixels.assign(out.prepared.scene.images.size(), PreparedScene::kNotDecoded);
    plan_and_reconstruct("scene", options, settled, out);
    return out;
}

} // namespace depthcull::pipeline
