// pipeline::plan_target: --target over a prepared scene. Each distinct
// image rect analyzed at a few vertex budgets with the profile's
// MIN_OPAQUE_AREA (through the cache, on threads), then the cost model's
// choose_for_target. Candidates are stored by index, so the plan never
// depends on the thread count.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

#include "depthcull/target.h"
#include "pipeline/parallel.h"

namespace depthcull::pipeline {

namespace {

// One plan; `clip` (issue 25): hidden parts are clipped, and when
// `occluders` the choice and MIN_OPAQUE_AREA price what opaque polygons
// hide as clipped away (free) rather than rejected.
TargetPlan plan_once(const PreparedScene& prepared, const PrepareOptions& options, const CostProfile& profile,
                     const ReconstructOptions& reconstruct, bool clip, bool occluders) {
    TargetPlan plan;
    plan.profile = profile;
    const Scene& scene = prepared.scene;
    AnalyzeOptions analyze = analysis_options(options, scene); // the settled filter
    plan.budgets = target_budgets(analyze.boundary.max_vertices);
    CostProfile priced = profile;
    if (occluders) priced.fragment_rejected_ns = 0;
    plan.min_opaque_area = min_opaque_area(priced);
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
    const std::vector<ImageView> views = prepared.views();
    parallel_for(keys * nb, options.threads, [&](std::size_t w) {
        const std::size_t k = w / nb, b = w % nb;
        if (first_use[k] == std::size_t(-1)) return;
        const Element& e = scene.elements[first_use[k]];
        AnalyzeOptions o = analyze;
        o.boundary.max_vertices = plan.budgets[b];
        bool h = false;
        const std::string& name = scene.images[std::size_t(e.image)].path;
        // An animated element's key is its animation's (prepare_scene): its
        // candidates too hold every frame's texels, or the chosen meshes
        // would cut off what frame 0 does not show.
        plan.candidates[w] = e.animation >= 0 ? analyze_animation(views, scene.animations[std::size_t(e.animation)], o, options.cache_dir, &h,
                                                                  name + ": animation " + std::to_string(e.animation), options.memory)
                                              : analyze_cached(views[std::size_t(e.image)], e.rect, o, options.cache_dir, &h, name, options.memory);
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
            candidates[k].analyses.push_back(&plan.candidate(k, b)); // local: the plan keeps none of these pointers
            candidates[k].max_vertices.push_back(plan.budgets[b]);
        }
    }
    ReconstructOptions chosen = reconstruct;
    chosen.depthless = options.depthless; // the chooser draws each plan with and without depth
    if (clip) chosen.clip_hidden = clip_hidden_options(profile);
    chosen.clip_hidden.plan_occluders = occluders;
    plan.choice = choose_for_target(scene, candidates, element_key, profile, chosen);
    plan.reconstruct = chosen;
    plan.reconstruct.clip_hidden.plan_occluders = false;
    plan.reconstruct.opaque_polygons = reconstruct.opaque_polygons && plan.choice.opaque_pass;
    plan.reconstruct.depthless = plan.choice.depthless;
    return plan;
}

// The plan for the opaque polygons options.analyze asks for: the plain
// plan, or the one planned for clipping where it is predicted faster.
TargetPlan plan_method(const PreparedScene& prepared, const PrepareOptions& options, const CostProfile& profile,
                       const ReconstructOptions& reconstruct) {
    // Issue 25: hidden parts clipped where the profile says it pays, and
    // opaque merging (it only takes triangles and edges away), each on
    // unless options turn it off (--no-clip-hidden, --no-merge-opaque).
    const bool clip = options.clip_hidden && clip_hidden_options(profile).enabled;
    ReconstructOptions base = reconstruct;
    base.merge_opaque = options.merge_opaque;
    TargetPlan plan = plan_once(prepared, options, profile, base, clip, false);
    if (!clip) return plan;
    // Planned for clipping too (more opaque polygons, priced as hiding for
    // free): kept only when the whole frame is predicted faster, as the
    // local estimates miss whether each cut pays.
    TargetPlan planned = plan_once(prepared, options, profile, base, true, true);
    if (planned.choice.predicted_ms < plan.choice.predicted_ms) {
        planned.analyzed += plan.analyzed;
        planned.cache_hits += plan.cache_hits;
        return planned;
    }
    plan.analyzed += planned.analyzed;
    plan.cache_hits += planned.cache_hits;
    return plan;
}

} // namespace

TargetPlan plan_target(const PreparedScene& prepared, const PrepareOptions& options, const CostProfile& profile,
                       const ReconstructOptions& reconstruct) {
    TargetPlan plan = plan_method(prepared, options, profile, reconstruct);
    // Issue 25 point 2: the default's few opaque polygons against the opaque
    // region cut into as many convex pieces as pay (OpaqueMethod::cover,
    // each piece worth MIN_OPAQUE_AREA texels), kept only when the whole
    // frame is predicted faster. --no-cover-plan turns it off (to measure
    // what it gains).
    if (!options.cover_plan || options.analyze.opaque.method != OpaqueMethod::fast || options.analyze.opaque.max_polygons <= 0)
        return plan;
    PrepareOptions cover_options = options;
    cover_options.analyze.opaque.method = OpaqueMethod::cover;
    cover_options.analyze.opaque.max_polygons = kCoverPlanPolygons;
    TargetPlan cover = plan_method(prepared, cover_options, profile, reconstruct);
    cover.opaque_cover = true;
    if (cover.choice.predicted_ms < plan.choice.predicted_ms) std::swap(cover, plan);
    plan.analyzed += cover.analyzed;
    plan.cache_hits += cover.cache_hits;
    return plan;
}

std::string target_summary(const std::string& path, const TargetPlan& plan) {
    const TargetChoice& c = plan.choice;
    auto print = [&](char* out, std::size_t size) {
        return std::snprintf(out, size,
                             "%s: --target %s: predicted %.3f ms (overpaint %.3f, meshes only %.3f); opaque pass %s, %lld elements with "
                             "opaque polygons (%lld given up per element), %lld hidden elements dropped, MIN_OPAQUE_AREA %d%s%s%s%s",
                             path.c_str(), plan.profile.name.c_str(), c.predicted_ms, c.overpaint_ms, c.meshes_only_ms,
                             c.opaque_pass ? "on" : "off", (long long)c.elements_opaque, (long long)c.elements_reverted,
                             (long long)c.elements_dropped, plan.min_opaque_area,
                             plan.opaque_cover ? "; opaque polygons: cover" : "", c.depthless ? "; no depth buffer" : "",
                             c.fallback.empty() ? "" : "; fallback: ", c.fallback.c_str());
    };
    std::string line(std::size_t(std::max(0, print(nullptr, 0))), '\0');
    print(line.data(), line.size() + 1);
    return line;
}

} // namespace depthcull::pipeline
