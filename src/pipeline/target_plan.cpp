// pipeline::plan_target: --target over a prepared scene. Each distinct
// image rect analyzed at a few vertex budgets with the profile's
// MIN_OPAQUE_AREA (through the cache, on threads), then the cost model's
// choose_for_target. Candidates are stored by index, so the plan never
// depends on the thread count.
#include <algorithm>
#include <cstdint>

#include "depthcull/pipeline.h"

namespace depthcull::pipeline {

TargetPlan plan_target(const PreparedScene& prepared, const PrepareOptions& options, const CostProfile& profile,
                       const ReconstructOptions& reconstruct) {
    TargetPlan plan;
    plan.profile = profile;
    const Scene& scene = prepared.scene;
    AnalyzeOptions analyze = options.analyze;
    analyze.filter = scene.filter; // prepare_scene set the winner there
    const int cap = std::max(kMinBoundaryVertices, analyze.boundary.max_vertices);
    for (int b : {4, 6, 8})
        if (b < cap) plan.budgets.push_back(b);
    plan.budgets.push_back(cap);
    plan.min_opaque_area = min_opaque_area(profile);
    analyze.opaque.min_area = plan.min_opaque_area;

    // Keys: the prepared scene's distinct analyses.
    const SceneAnalysis& analysis = prepared.analysis;
    std::vector<int> element_key(scene.elements.size(), -1);
    std::vector<std::size_t> first_use(analysis.images.size(), std::size_t(-1));
    for (std::size_t i = 0; i < scene.elements.size(); ++i) {
        if (!analysis.of(i)) continue;
        const std::size_t k = analysis.of_element[i];
        element_key[i] = int(k);
        if (first_use[k] == std::size_t(-1)) first_use[k] = i;
    }
    const std::size_t keys = analysis.images.size(), nb = plan.budgets.size();
    plan.candidates.resize(keys * nb);
    std::vector<std::uint8_t> hit(keys * nb, 0);
    parallel_for(keys * nb, options.threads, [&](std::size_t w) {
        const std::size_t k = w / nb, b = w % nb;
        if (first_use[k] == std::size_t(-1)) return;
        const Element& e = scene.elements[first_use[k]];
        AnalyzeOptions o = analyze;
        o.boundary.max_vertices = plan.budgets[b];
        bool h = false;
        plan.candidates[w] = analyze_cached(prepared.view(std::size_t(e.image)), e.rect, o, options.cache_dir, &h,
                                             scene.images[std::size_t(e.image)].path, options.memory);
        hit[w] = h;
    });
    for (std::size_t w = 0; w < keys * nb; ++w) {
        if (first_use[w / nb] == std::size_t(-1)) continue;
        plan.cache_hits += hit[w];
        plan.analyzed += !hit[w];
    }
    std::vector<TargetCandidates> candidates(keys);
    for (std::size_t k = 0; k < keys; ++k) {
        if (first_use[k] == std::size_t(-1)) continue;
        for (std::size_t b = 0; b < nb; ++b) {
            candidates[k].analyses.push_back(&plan.candidates[k * nb + b]);
            candidates[k].max_vertices.push_back(plan.budgets[b]);
        }
    }
    plan.choice = choose_for_target(scene, candidates, element_key, profile, reconstruct);
    plan.analysis = plan.choice.analysis; // a value already: indices into its own images
    plan.reconstruct = reconstruct;
    plan.reconstruct.opaque_polygons = reconstruct.opaque_polygons && plan.choice.opaque_pass;
    return plan;
}

} // namespace depthcull::pipeline
