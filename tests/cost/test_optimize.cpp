// Issue 22: pipeline::optimize, the one call every entry point makes;
// settle, the one place the texture filter and the target profile are
// decided; TargetPlan as a value.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "depthcull/analyze.h"
#include "depthcull/pipeline.h"
#include "depthcull/target.h"
#include "testing/io_error.h"

namespace depthcull::test {
namespace {

std::string meadow() { return std::string(DEPTHCULL_SOURCE_DIR) + "/examples/meadow.json"; }

// The meshes as drawn: every draw's vertices, indices, image, pass and
// blend, and the filter they were made for.
void expect_same_meshes(const SceneMeshes& a, const SceneMeshes& b) {
    EXPECT_EQ(a.filter, b.filter);
    EXPECT_EQ(a.stats.triangles, b.stats.triangles);
    EXPECT_EQ(a.stats.depth_levels, b.stats.depth_levels);
    ASSERT_EQ(a.draws.size(), b.draws.size());
    for (std::size_t i = 0; i < a.draws.size(); ++i) {
        EXPECT_EQ(a.draws[i].image, b.draws[i].image) << "draw " << i;
        EXPECT_EQ(a.draws[i].pass, b.draws[i].pass) << "draw " << i;
        EXPECT_EQ(a.draws[i].blend, b.draws[i].blend) << "draw " << i;
        EXPECT_EQ(a.draws[i].vertices, b.draws[i].vertices) << "draw " << i;
        EXPECT_EQ(a.draws[i].indices, b.draws[i].indices) << "draw " << i;
    }
}

// A TargetPlan is a value: a copy outlives the original and finds its
// candidates by index in itself. (The candidates were a std::deque whose
// elements' addresses the choice once held, so a copy pointed into the
// original.)
TEST(TargetPlan, ACopyOutlivesTheOriginal) {
    pipeline::PrepareOptions o;
    o.threads = 1;
    const pipeline::PreparedScene prepared = pipeline::prepare_scene(meadow(), o);
    auto original = std::make_unique<pipeline::TargetPlan>(pipeline::plan_target(prepared, o, pipeline::resolve_target("llvmpipe"), {}));
    SceneMeshes expected;
    ASSERT_EQ(reconstruct_scene(prepared.scene, original->choice.analysis, original->reconstruct, &expected), ReconstructStatus::ok);
    const std::vector<ImageAnalysis> candidates = original->candidates;
    const pipeline::TargetPlan copy = *original;
    original.reset();

    ASSERT_EQ(copy.candidates.size(), prepared.analysis.images.size() * copy.budgets.size());
    for (std::size_t k = 0; k < prepared.analysis.images.size(); ++k)
        for (std::size_t b = 0; b < copy.budgets.size(); ++b) {
            const ImageAnalysis& c = copy.candidate(k, b);
            EXPECT_EQ(&c, &copy.candidates[k * copy.budgets.size() + b]);
            EXPECT_EQ(c.boundary, candidates[k * copy.budgets.size() + b].boundary);
        }
    ASSERT_EQ(copy.choice.analysis.of_element.size(), prepared.scene.elements.size());
    SceneMeshes got;
    ASSERT_EQ(reconstruct_scene(prepared.scene, copy.choice.analysis, copy.reconstruct, &got), ReconstructStatus::ok);
    expect_same_meshes(got, expected);
}

// plan_target's choices (one per plan weighed, each rasterizing dozens of
// contestant frames) reserve target_choice_bytes from the run's memory
// budget before they run: with room for one, eight threads choose one plan
// at a time, and choose what one thread chooses.
TEST(TargetPlan, ChoicesReserveFromTheBudgetAndChooseAsWithOneThread) {
    pipeline::PrepareOptions o;
    o.threads = 1;
    const pipeline::PreparedScene prepared = pipeline::prepare_scene(meadow(), o);
    const CostProfile profile = pipeline::resolve_target("llvmpipe");
    const pipeline::TargetPlan single = pipeline::plan_target(prepared, o, profile, {});
    const std::uint64_t one = pipeline::target_choice_bytes(prepared.scene);
    EXPECT_EQ(one, pipeline::kTargetChoiceFixedBytes + pipeline::kTargetChoiceBytesPerElement * prepared.scene.elements.size());
    pipeline::MemoryBudget budget(one + one / 2);
    pipeline::PrepareOptions eight = o;
    eight.threads = 8;
    eight.memory = &budget;
    const pipeline::TargetPlan many = pipeline::plan_target(prepared, eight, profile, {});
    EXPECT_EQ(budget.peak(), one); // the candidates' analyses reserve less, and before
    EXPECT_EQ(many.choice.predicted_ms, single.choice.predicted_ms);
    SceneMeshes a, b;
    ASSERT_EQ(reconstruct_scene(prepared.scene, single.choice.analysis, single.reconstruct, &a), ReconstructStatus::ok);
    ASSERT_EQ(reconstruct_scene(prepared.scene, many.choice.analysis, many.reconstruct, &b), ReconstructStatus::ok);
    expect_same_meshes(b, a);
}

// Past max_target_elements (kMaxTargetElements) a scene is planned without
// its target, with one warning naming the limit, and reconstructed as
// without a target; --strict refuses it.
TEST(Optimize, PastMaxTargetElementsPlansWithoutATargetAndWarns) {
    pipeline::OptimizeOptions o;
    o.prepare.threads = 1;
    o.target = "llvmpipe";
    o.max_target_elements = 3;
    std::vector<std::string> warnings;
    o.prepare.load.warning = [&](const std::string& w) { warnings.push_back(w); };
    const pipeline::OptimizeResult r = pipeline::optimize(meadow(), o);
    ASSERT_EQ(r.status, ReconstructStatus::ok);
    EXPECT_FALSE(r.plan);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(has(warnings[0], "meadow.json: 459 elements, more than the 3 --target weighs (kMaxTargetElements)")) << warnings[0];
    pipeline::OptimizeOptions plain;
    plain.prepare.threads = 1;
    const pipeline::OptimizeResult expected = pipeline::optimize(meadow(), plain);
    ASSERT_EQ(expected.status, ReconstructStatus::ok);
    expect_same_meshes(r.meshes, expected.meshes);
    o.max_target_elements = 459; // at the limit: planned
    EXPECT_TRUE(pipeline::optimize(meadow(), o).plan);
    o.max_target_elements = 3;
    o.prepare.load.strict = true;
    const std::string e = io_error([&] { pipeline::optimize(meadow(), o); });
    EXPECT_TRUE(has(e, "(kMaxTargetElements)")) << e;
    EXPECT_TRUE(has(e, "(--strict)")) << e;
}

TEST(Settle, AGivenFilterWinsOverTheScenes) {
    Scene scene;
    scene.filter = Filter::linear;
    pipeline::OptimizeOptions o;
    EXPECT_EQ(pipeline::settle(scene, o).filter, Filter::linear);
    EXPECT_FALSE(pipeline::settle(scene, o).profile);
    o.prepare.filter = Filter::nearest;
    EXPECT_EQ(pipeline::settle(scene, o).filter, Filter::nearest);
    scene.filter = Filter::nearest;
    o.prepare.filter = Filter::linear;
    EXPECT_EQ(pipeline::settle(scene, o).filter, Filter::linear);
    // The analysis options take the scene's (settled) filter, never the
    // one left in PrepareOptions::analyze.
    o.prepare.analyze.filter = Filter::nearest;
    EXPECT_EQ(pipeline::analysis_options(o.prepare, scene).filter, Filter::nearest);
    scene.filter = Filter::linear;
    EXPECT_EQ(pipeline::analysis_options(o.prepare, scene).filter, Filter::linear);
}

TEST(Settle, TheTargetIsResolvedOnce) {
    pipeline::OptimizeOptions o;
    o.target = "llvmpipe";
    const pipeline::Settled s = pipeline::settle(Scene{}, o);
    ASSERT_TRUE(s.profile);
    EXPECT_EQ(s.profile->name, "llvmpipe");
    o.target = "no-such-profile";
    EXPECT_TRUE(has(io_error([&] { pipeline::settle(Scene{}, o); }), "--target: 'no-such-profile'"));
}

// --filter linear on a scene of nearest sprites: the settled filter reaches
// the analysis (its polygons are the linear ones), the scene the result
// holds and the meshes.
TEST(Optimize, TheSettledFilterReachesEveryStage) {
    pipeline::OptimizeOptions o;
    o.prepare.threads = 1;
    o.prepare.filter = Filter::linear;
    const pipeline::OptimizeResult r = pipeline::optimize(meadow(), o);
    ASSERT_EQ(r.status, ReconstructStatus::ok);
    EXPECT_EQ(r.prepared.scene.filter, Filter::linear);
    EXPECT_EQ(r.meshes.filter, Filter::linear);
    ASSERT_FALSE(r.prepared.scene.elements.empty());
    const Element& e = r.prepared.scene.elements[0];
    AnalyzeOptions linear;
    linear.filter = Filter::linear;
    const ImageAnalysis expected = analyze_image(r.prepared.view(std::size_t(e.image)), e.rect, linear);
    ASSERT_TRUE(r.prepared.analysis.of(0));
    EXPECT_EQ(r.prepared.analysis.of(0)->boundary, expected.boundary);
    EXPECT_EQ(r.prepared.analysis.of(0)->opaque, expected.opaque);
}

// optimize is its stages strung together, nothing more: the same meshes as
// prepare_scene, plan_target and reconstruct_scene called in turn.
TEST(Optimize, EqualsItsStagesInTurn) {
    pipeline::OptimizeOptions o;
    o.prepare.threads = 1;
    o.target = "llvmpipe";
    const pipeline::OptimizeResult r = pipeline::optimize(meadow(), o);
    ASSERT_EQ(r.status, ReconstructStatus::ok);
    ASSERT_TRUE(r.plan);
    EXPECT_EQ(r.plan->profile.name, "llvmpipe");

    const pipeline::PreparedScene prepared = pipeline::prepare_scene(meadow(), o.prepare);
    const pipeline::TargetPlan plan = pipeline::plan_target(prepared, o.prepare, pipeline::resolve_target("llvmpipe"), o.reconstruct);
    SceneMeshes expected;
    ASSERT_EQ(reconstruct_scene(prepared.scene, plan.choice.analysis, plan.reconstruct, &expected), ReconstructStatus::ok);
    expect_same_meshes(r.meshes, expected);
    EXPECT_EQ(r.prepared.analysis.of_element, plan.choice.analysis.of_element);
    EXPECT_EQ(r.reconstruct.opaque_polygons, plan.reconstruct.opaque_polygons);
}

// The C API's path: a scene and analyses already in memory give the meshes
// the file gives; a target needs the pixels, which are not there.
TEST(Optimize, ASceneInMemoryGivesTheFilesMeshes) {
    pipeline::OptimizeOptions o;
    o.prepare.threads = 1;
    const pipeline::OptimizeResult from_file = pipeline::optimize(meadow(), o);
    ASSERT_EQ(from_file.status, ReconstructStatus::ok);
    const pipeline::OptimizeResult in_memory =
        pipeline::optimize(pipeline::SceneSource{from_file.prepared.scene, from_file.prepared.analysis}, o);
    ASSERT_EQ(in_memory.status, ReconstructStatus::ok);
    expect_same_meshes(in_memory.meshes, from_file.meshes);
    o.target = "llvmpipe";
    const pipeline::SceneSource source{from_file.prepared.scene, from_file.prepared.analysis};
    EXPECT_TRUE(has(io_error([&] { pipeline::optimize(source, o); }), "needs the scene's pixels"));
    // A profile the caller resolved (the CLI's --target auto) needs them too.
    o.target.clear();
    o.profile = pipeline::resolve_target("llvmpipe");
    EXPECT_TRUE(has(io_error([&] { pipeline::optimize(source, o); }), "target llvmpipe: planning needs the scene's pixels"));
}

// Without meshes asked for (render, bench, report build each mode's own),
// the stages before reconstruction still run and nothing is built.
TEST(Optimize, WithoutMeshesStopsAfterThePlan) {
    pipeline::OptimizeOptions o;
    o.prepare.threads = 1;
    o.reconstruct_meshes = false;
    const pipeline::OptimizeResult r = pipeline::optimize(meadow(), o);
    EXPECT_TRUE(r.meshes.draws.empty());
    EXPECT_EQ(r.prepared.analysis.of_element.size(), r.prepared.scene.elements.size());
}

} // namespace
} // namespace depthcull::test
