// pipeline::plan_target: --target over a prepared scene. Each distinct
// image rect analyzed at a few vertex budgets with the profile's
// MIN_OPAQUE_AREA (through the cache, on threads), then the cost model's
// choose_for_target for each plan weighed, side by side on threads (each
// rasterizes dozens of contestant frames on the CPU: most of
// `optimize --target`'s time). Candidates and plans are stored by index
// and settled in a fixed order, so the plan never depends on the thread
// count.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>

#include "depthcull/target.h"
#include "pipeline/parallel.h"

namespace depthcull::pipeline {

namespace {

// One plan to weigh: PrepareOptions' opaque method, and `clip` (issue 25):
// hidden parts are clipped, and when `occluders` the choice and
// MIN_OPAQUE_AREA price what opaque polygons hide as clipped away (free)
// rather than rejected.
struct PlanJob {
    const PrepareOptions* options;
    bool clip, occluders;
    TargetPlan plan;
    std::vector<int> element_key;
};

// The job's candidates: each distinct rect of the prepared scene analyzed
// at the plan's vertex budgets with its MIN_OPAQUE_AREA (through the
// cache, on threads).
void analyze_candidates(const PreparedScene& prepared, const CostProfile& profile, PlanJob& job) {
    const PrepareOptions& options = *job.options;
    TargetPlan& plan = job.plan;
    plan.profile = profile;
    const Scene& scene = prepared.scene;
    AnalyzeOptions analyze = analysis_options(options, scene); // the settled filter
    plan.budgets = target_budgets(analyze.boundary.max_vertices);
    CostProfile priced = profile;
    if (job.occluders) priced.fragment_rejected_ns = 0;
    plan.min_opaque_area = min_opaque_area(priced);
    analyze.opaque.min_area = plan.min_opaque_area;

    // Keys: the prepared scene's distinct analyses.
    const SceneAnalysis& analysis = prepared.analysis;
    job.element_key.assign(scene.elements.size(), -1);
    std::vector<std::size_t> first_use(analysis.images.size(), std::size_t(-1));
    for (std::size_t i = 0; i < scene.elements.size(); ++i) {
        if (!analysis.of(i)) continue;
        const std::size_t k = analysis.of_element[i];
        job.element_key[i] = int(k);
        if (first_use[k] == std::size_t(-1)) first_use[k] = i;
    }
    const std::size_t keys = analysis.images.size(), nb = plan.budgets.size();
    plan.candidates.resize(keys * nb);
    std::vector<std::uint8_t> hit(keys * nb, 0), used(keys * nb, 0);
    const std::vector<ImageView> views = prepared.views();
    parallel_for(keys * nb, options.threads, [&](std::size_t w) {
        const std::size_t k = w / nb, b = w % nb;
        if (first_use[k] == std::size_t(-1)) return;
        used[w] = 1;
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
        plan.cache_hits += hit[w];
        plan.analyzed += used[w] && !hit[w];
    }
}

// The job's choice among its candidates (choose_for_target). Reads only
// the job and the prepared scene, so jobs choose on threads side by side.
void choose(const PreparedScene& prepared, const CostProfile& profile, const ReconstructOptions& reconstruct, PlanJob& job) {
    TargetPlan& plan = job.plan;
    const std::size_t nb = plan.budgets.size(), keys = nb ? plan.candidates.size() / nb : 0;
    std::vector<std::uint8_t> used(keys, 0); // one pass: a search per key took keys x elements
    for (int k : job.element_key)
        if (k >= 0 && std::size_t(k) < keys) used[std::size_t(k)] = 1;
    std::vector<TargetCandidates> candidates(keys);
    for (std::size_t k = 0; k < keys; ++k) {
        if (!used[k]) continue;
        for (std::size_t b = 0; b < nb; ++b) {
            candidates[k].analyses.push_back(&plan.candidate(k, b)); // local: the plan keeps none of these pointers
            candidates[k].max_vertices.push_back(plan.budgets[b]);
        }
    }
    ReconstructOptions chosen = reconstruct;
    chosen.merge_opaque = job.options->merge_opaque;
    chosen.depthless = job.options->depthless; // the chooser draws each plan with and without depth
    if (job.clip) chosen.clip_hidden = clip_hidden_options(profile);
    chosen.clip_hidden.plan_occluders = job.occluders;
    plan.choice = choose_for_target(prepared.scene, candidates, job.element_key, profile, chosen);
    plan.reconstruct = chosen;
    plan.reconstruct.clip_hidden.plan_occluders = false;
    plan.reconstruct.opaque_polygons = reconstruct.opaque_polygons && plan.choice.opaque_pass;
    plan.reconstruct.depthless = plan.choice.depthless;
}

// `other`'s plan when predicted faster than `plan`'s (ties keep `plan`),
// the analysis counts of both.
void keep_faster(TargetPlan& plan, TargetPlan& other) {
    if (other.choice.predicted_ms < plan.choice.predicted_ms) std::swap(plan, other);
    plan.analyzed += other.analyzed;
    plan.cache_hits += other.cache_hits;
}

} // namespace

TargetPlan plan_target(const PreparedScene& prepared, const PrepareOptions& options, const CostProfile& profile,
                       const ReconstructOptions& reconstruct) {
    // The plans weighed, in the order ties are settled:
    // - the default's opaque polygons: the plain plan and (issue 25), where
    //   the profile says clipping hidden parts pays, the one planned for
    //   clipping (more opaque polygons, priced as hiding for free), kept
    //   only when the whole frame is predicted faster, as the local
    //   estimates miss whether each cut pays; --no-clip-hidden turns it off;
    // - issue 25 point 2: the same with the opaque region cut into as many
    //   convex pieces as pay (OpaqueMethod::cover, each piece worth
    //   MIN_OPAQUE_AREA texels), kept only when predicted faster than the
    //   first; --no-cover-plan turns it off (to measure what it gains).
    // Opaque merging (it only takes triangles and edges away) is on unless
    // --no-merge-opaque.
    const bool clip = options.clip_hidden && clip_hidden_options(profile).enabled;
    const PrepareOptions cover_options = [&] {
        PrepareOptions o = options;
        o.analyze.opaque.method = OpaqueMethod::cover;
        o.analyze.opaque.max_polygons = kCoverPlanPolygons;
        return o;
    }();
    const bool cover = options.cover_plan && options.analyze.opaque.method == OpaqueMethod::fast && options.analyze.opaque.max_polygons > 0;
    std::vector<const PrepareOptions*> methods{&options};
    if (cover) methods.push_back(&cover_options);
    std::vector<PlanJob> jobs; // per method: the plain plan, then (clip) the one planned for clipping
    for (const PrepareOptions* o : methods) {
        jobs.push_back({o, clip, false, {}, {}});
        if (clip) jobs.push_back({o, true, true, {}, {}});
    }
    // Candidates first (each analysis on threads, through the cache), then
    // the choices side by side, each once its memory is reserved: each
    // rasterizes its contestants' frames alone.
    for (PlanJob& job : jobs) analyze_candidates(prepared, profile, job);
    MemoryBudget& memory = options.memory ? *options.memory : shared_memory_budget();
    const std::uint64_t choice_bytes = target_choice_bytes(prepared.scene);
    parallel_for(jobs.size(), options.threads, [&](std::size_t j) {
        const MemoryBudget::Hold hold = memory.reserve(choice_bytes);
        choose(prepared, profile, reconstruct, jobs[j]);
    });

    std::vector<TargetPlan> by_method;
    for (std::size_t j = 0; j < jobs.size(); j += clip ? 2 : 1) {
        TargetPlan plan = std::move(jobs[j].plan);
        if (clip) keep_faster(plan, jobs[j + 1].plan);
        by_method.push_back(std::move(plan));
    }
    TargetPlan plan = std::move(by_method[0]);
    if (by_method.size() > 1) {
        by_method[1].opaque_cover = true;
        keep_faster(plan, by_method[1]);
    }
    return plan;
}

std::uint64_t target_choice_bytes(const Scene& scene) {
    return kTargetChoiceFixedBytes + kTargetChoiceBytesPerElement * std::uint64_t(scene.elements.size());
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
