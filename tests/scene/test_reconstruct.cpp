// Paper 2.3.1-2.3.3 on small scenes with exact expected orders, depth
// levels and draw counts, and properties on random scenes: the blend order
// respects every graph edge, overlapping elements never share a level.
#include <algorithm>
#include <map>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "scene_fixtures.h"

namespace depthcull::test {
namespace {

using Order = std::vector<std::uint32_t>;

int count_pass(const SceneMeshes& m, Pass p) {
    return int(std::count_if(m.draws.begin(), m.draws.end(), [&](const Draw& d) { return d.pass == p; }));
}

TEST(SortElements, IndependentElementsOfOneImageBatch) {
    SceneBuilder b;
    int a = b.image("a", 10, 10), c = b.image("c", 10, 10);
    b.add(a, b.full(a), 0, 0);
    b.add(c, b.full(c), 20, 0);
    b.add(a, b.full(a), 40, 0);
    b.add(c, b.full(c), 60, 0);
    ElementGraph g = build_element_graph(b.scene, b.analyses, GraphMode::polygons);
    for (SortMethod m : {SortMethod::paper, SortMethod::batch}) {
        Order order = sort_elements(b.scene, g, m);
        EXPECT_EQ(order, (Order{0, 2, 1, 3})) << int(m);
        EXPECT_EQ(count_batches(b.scene, order), 2);
    }
    EXPECT_EQ(count_batches(b.scene, sort_elements(b.scene, g, SortMethod::none)), 4);
}

TEST(SortElements, NeverMovesAnElementAcrossOneItObscures) {
    // a0, c1, a2 where a2 overlaps c1: a2 must stay after c1 (paper 2.3.1).
    SceneBuilder b;
    int a = b.image("a", 10, 10), c = b.image("c", 10, 10);
    b.add(a, b.full(a), 0, 0);
    b.add(c, b.full(c), 20, 0);
    b.add(a, b.full(a), 25, 5);
    ElementGraph g = build_element_graph(b.scene, b.analyses, GraphMode::polygons);
    for (SortMethod m : {SortMethod::paper, SortMethod::batch, SortMethod::none}) {
        Order order = sort_elements(b.scene, g, m);
        EXPECT_EQ(order, (Order{0, 1, 2})) << int(m);
    }
}

TEST(SortElements, BlockedElementsWaitOthersJoinTheirRun) {
    // a0 b1 a2 b3 with a2 over b1 only: a2 cannot join a0 (it must stay
    // after b1), b3 joins b1: a0 b1 b3 a2, 3 runs; painter's order has 4.
    SceneBuilder b;
    int a = b.image("a", 10, 10), c = b.image("b", 10, 10);
    b.add(a, b.full(a), 0, 0);
    b.add(c, b.full(c), 20, 0);
    b.add(a, b.full(a), 25, 0);
    b.add(c, b.full(c), 60, 0);
    ElementGraph g = build_element_graph(b.scene, b.analyses, GraphMode::polygons);
    Order order = sort_elements(b.scene, g, SortMethod::batch);
    EXPECT_EQ(count_batches(b.scene, order), 3);
    EXPECT_EQ(count_batches(b.scene, sort_elements(b.scene, g, SortMethod::none)), 4);
}

TEST(SortElements, ImagesSharingAFileShareAMeshBlendModesDoNot) {
    SceneBuilder b;
    int t1 = b.image("tile1", 10, 10, "tiles.png"), t2 = b.image("tile2", 10, 10, "tiles.png");
    b.add(t1, b.full(t1), 0, 0);
    b.add(t2, b.full(t2), 20, 0);
    b.add(t1, b.full(t1), 40, 0, Blend::add);
    EXPECT_TRUE(can_share_mesh(b.scene, b.scene.elements[0], b.scene.elements[1]));
    EXPECT_FALSE(can_share_mesh(b.scene, b.scene.elements[0], b.scene.elements[2]));
    ElementGraph g = build_element_graph(b.scene, b.analyses, GraphMode::polygons);
    EXPECT_EQ(count_batches(b.scene, sort_elements(b.scene, g, SortMethod::batch)), 2);
}

TEST(DepthValues, LongestPathKeepsTheRangeSmall) {
    // Chain 0 <- 1 <- 2, element 3 overlaps only 0, 4 alone: levels are
    // longest paths, not positions.
    SceneBuilder b;
    int sq = b.image("sq", 10, 10);
    const ImageAnalysis* a = b.full(sq);
    b.add(sq, a, 0, 0);
    b.add(sq, a, 8, 0);
    b.add(sq, a, 16, 0);
    b.add(sq, a, -5, 8);
    b.add(sq, a, 100, 100);
    ElementGraph g = build_element_graph(b.scene, b.analyses, GraphMode::polygons);
    EXPECT_EQ(assign_depth_levels(g), (std::vector<std::int64_t>{0, 1, 2, 1, 0}));
    SceneMeshes m;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, {}, &m), ReconstructStatus::ok);
    EXPECT_EQ(m.stats.depth_levels, 3);
    EXPECT_EQ(m.stats.graph_edges, 3);
    EXPECT_EQ(m.stats.depth_bits, 10); // D = 256: fits 16-bit buffers
}

TEST(DepthValues, MappingIsExactAndOrdered) {
    const std::int64_t d = depth_denominator(kMaxDepthLevels);
    EXPECT_EQ(d, std::int64_t(1) << 22);
    float prev = 0;
    for (std::int64_t k : {std::int64_t(0), std::int64_t(1), kMaxDepthLevels - 2, kMaxDepthLevels - 1}) {
        float boundary = depth_z(k, false, d), opaque = depth_z(k, true, d);
        EXPECT_GT(boundary, prev);
        EXPECT_GT(opaque, boundary);
        EXPECT_LE(opaque, 1.0f);
        EXPECT_EQ(double(boundary) * double(d), double(2 * k + 1)); // exact in a float
        prev = opaque;
    }
}

TEST(GenerateMeshes, OpaquePassMergesAnImageRegardlessOfOrder) {
    // a0 b1 a2 a3 where b1 overlaps a0 and a2: blend runs a | b | a, but
    // the opaque pass needs one draw per image.
    SceneBuilder b;
    int a = b.image("a", 10, 10), c = b.image("b", 10, 10);
    b.add(a, b.full_opaque(a), 0, 0);
    b.add(c, b.full_opaque(c), 5, 0);
    b.add(a, b.full_opaque(a), 12, 0);
    b.add(a, b.full_opaque(a), 100, 0);
    SceneMeshes m;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, {}, &m), ReconstructStatus::ok);
    EXPECT_TRUE(m.depth_test);
    EXPECT_EQ(count_pass(m, Pass::opaque), 2);
    EXPECT_EQ(count_pass(m, Pass::blend), 3);
    EXPECT_EQ(m.stats.draw_calls, 5);
    EXPECT_EQ(m.stats.triangles, 4 * 2 + 4 * 2);
    // Opaque draws come first, front to back: a (a2 is level 2) before b
    // (level 1), a2 first within its draw.
    EXPECT_EQ(m.stats.depth_levels, 3);
    EXPECT_EQ(m.draws[0].pass, Pass::opaque);
    EXPECT_EQ(m.draws[0].image, a);
    EXPECT_EQ(m.draws[1].image, c);
    const std::int64_t d = depth_denominator(3);
    EXPECT_EQ(m.draws[0].vertices[2], depth_z(2, true, d));
    EXPECT_EQ(m.draws[1].vertices[2], depth_z(1, true, d));
    EXPECT_EQ(m.draws[2].pass, Pass::blend);
    EXPECT_EQ(m.draws[2].vertices[2], depth_z(0, false, d));
}

TEST(GenerateMeshes, TranslucentTintAndBlendRules) {
    SceneBuilder b;
    int a = b.image("a", 10, 10);
    const ImageAnalysis* an = b.full_opaque(a);
    b.add(a, an, 0, 0, Blend::alpha, 0.5f); // colour alpha < 1: no opaque polygons
    b.add(a, an, 20, 0, Blend::add);        // add: none either
    b.add(a, an, 40, 0, Blend::opaque);     // whole rect, opaque pass only
    b.add(a, b.analysis(a, {}), 60, 0);     // draws nothing
    SceneMeshes m;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, {}, &m), ReconstructStatus::ok);
    EXPECT_EQ(count_pass(m, Pass::opaque), 1);
    EXPECT_EQ(m.draws[0].blend, Blend::opaque);
    EXPECT_EQ(count_pass(m, Pass::blend), 2); // alpha and add differ
    EXPECT_EQ(m.stats.triangles, 6);

    ReconstructOptions no_opaque;
    no_opaque.opaque_polygons = false;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, no_opaque, &m), ReconstructStatus::ok);
    EXPECT_FALSE(m.depth_test);
    EXPECT_EQ(count_pass(m, Pass::opaque), 0);
    EXPECT_EQ(count_pass(m, Pass::blend), 3);
}

TEST(GenerateMeshes, VerticesFollowTheTransformAndRect) {
    SceneBuilder b;
    int atlas = b.image("atlas", 64, 32);
    auto an = std::make_unique<ImageAnalysis>();
    an->rect = {16, 8, 8, 8};
    an->boundary = {{{18, 8}, {24, 8}, {24, 16}, {16, 16}}};
    Element e;
    e.image = atlas;
    e.rect = an->rect;
    e.transform = {2, 0, 0, 2, 100, 50};
    b.scene.elements.push_back(e);
    b.analyses.push_back(an.get());
    SceneMeshes m;
    ReconstructOptions paper_meshes;
    paper_meshes.texel_margin = 0; // the polygon's own vertices only
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, paper_meshes, &m), ReconstructStatus::ok);
    ASSERT_EQ(m.draws.size(), 1u);
    const std::vector<float>& v = m.draws[0].vertices;
    ASSERT_EQ(v.size(), 4u * kVertexFloats);
    EXPECT_EQ(v[0], 104.0f); // (18 - 16) * 2 + 100
    EXPECT_EQ(v[1], 50.0f);
    EXPECT_EQ(v[3], 18.0f / 64);
    EXPECT_EQ(v[4], 8.0f / 32);
    EXPECT_EQ(m.draws[0].triangle_count(), 2u);
}

TEST(Reconstruct, InvalidScenesAreRejected) {
    SceneBuilder b;
    int a = b.image("a", 10, 10);
    b.add(a, b.full(a), 0, 0);
    SceneMeshes m;
    std::vector<const ImageAnalysis*> missing{nullptr};
    EXPECT_EQ(reconstruct_scene(b.scene, missing, {}, &m), ReconstructStatus::invalid_scene);
    b.scene.elements[0].transform[0] = NAN;
    EXPECT_EQ(reconstruct_scene(b.scene, b.analyses, {}, &m), ReconstructStatus::invalid_scene);
    b.scene.elements[0].transform[0] = 1;
    b.scene.elements[0].image = 5;
    EXPECT_EQ(reconstruct_scene(b.scene, b.analyses, {}, &m), ReconstructStatus::invalid_scene);
}

TEST(Reconstruct, EmptyAndAbsurdScenes) {
    SceneBuilder b;
    SceneMeshes m;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, {}, &m), ReconstructStatus::ok);
    EXPECT_EQ(m.stats.draw_calls, 0);
    int a = b.image("a", 10, 10);
    b.add(a, b.full(a), 0, 0);
    b.add(a, b.full(a), 1e300, -1e300);
    b.scene.elements[1].transform[0] = 1e300;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, {}, &m), ReconstructStatus::ok); // terminates
}

TEST(DynamicElements, TakeLevelsAboveTheStaticSceneInDrawingOrder) {
    SceneBuilder b;
    int a = b.image("a", 10, 10), c = b.image("c", 10, 10);
    b.add(a, b.full_opaque(a), 0, 0);
    b.add(a, b.full_opaque(a), 5, 0);
    ReconstructOptions o;
    o.reserved_dynamic_levels = 200;
    SceneMeshes base, frame;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, o, &base), ReconstructStatus::ok);
    EXPECT_EQ(base.stats.depth_levels, 2);
    const std::int64_t d = depth_denominator(2 + 200);
    EXPECT_EQ(d, 512);
    std::vector<Element> moving(3, b.scene.elements[0]);
    moving[1].image = c;
    std::vector<const ImageAnalysis*> an{b.full(a), b.full(c), b.full(a)};
    ASSERT_EQ(add_dynamic_elements(base, b.scene, moving, an, &frame), ReconstructStatus::ok);
    // Only the dynamic draws, a | c | a in the blend pass; the static ones
    // (1 opaque + 1 blend) are not copied.
    EXPECT_EQ(base.depth_denominator, d);
    ASSERT_EQ(frame.draws.size(), 3u);
    EXPECT_EQ(frame.stats.depth_levels, 5);
    EXPECT_EQ(frame.stats.draw_calls, 3);
    EXPECT_EQ(frame.draws.back().vertices[2], depth_z(4, false, d));
    EXPECT_EQ(frame.draws[0].vertices[2], depth_z(2, false, d));
    EXPECT_EQ(compose_frame(base, frame).draws.size(), base.draws.size() + 3);
    // Beyond what the depth mapping has room for.
    std::vector<Element> crowd(300, b.scene.elements[0]);
    std::vector<const ImageAnalysis*> crowd_an(300, b.full(a));
    EXPECT_EQ(add_dynamic_elements(base, b.scene, crowd, crowd_an, &frame), ReconstructStatus::too_many_depth_levels);
}

TEST(Reconstruct, CullToViewportDropsOnlyElementsEntirelyOutside) {
    SceneBuilder b;
    b.scene.viewport = {0, 0, 100, 100};
    int a = b.image("a", 10, 10);
    b.add(a, b.full(a), 50, 50);
    b.add(a, b.full(a), 95, 95);   // partly inside
    b.add(a, b.full(a), 120, 0);   // outside
    b.add(a, b.full(a), -30, -30); // outside
    ReconstructOptions o;
    o.cull_to_viewport = true;
    SceneMeshes m;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, o, &m), ReconstructStatus::ok);
    EXPECT_EQ(m.stats.triangles, 4);
    ASSERT_EQ(rectangle_meshes(b.scene, o, &m), ReconstructStatus::ok);
    EXPECT_EQ(m.stats.triangles, 4);
}

TEST(Reconstruct, RectangleMeshesBatchWithoutDepth) {
    SceneBuilder b;
    int a = b.image("a", 10, 10), c = b.image("c", 10, 10);
    b.add(a, b.full(a), 0, 0);
    b.add(c, b.full(c), 20, 0);
    b.add(a, b.full(a), 40, 0);
    SceneMeshes m;
    ASSERT_EQ(rectangle_meshes(b.scene, {}, &m), ReconstructStatus::ok);
    EXPECT_FALSE(m.depth_test);
    EXPECT_EQ(m.stats.draw_calls, 2);
    EXPECT_EQ(m.stats.triangles, 6);
    EXPECT_EQ(overpaint_meshes(b.scene).stats.draw_calls, 3);
}

// Random scenes with rotations, scales and several images.
SceneBuilder random_scene(int n, int images) {
    SceneBuilder b;
    std::vector<const ImageAnalysis*> an;
    for (int k = 0; k < images; ++k) {
        int w = *rc::gen::inRange(2, 30), h = *rc::gen::inRange(2, 30);
        b.image("i" + std::to_string(k), w, h, "file" + std::to_string(k % 3) + ".png");
        double x = w, y = h;
        // An octagon-ish boundary and an inner opaque quad.
        Polygon boundary{{x / 2, 0}, {x, y / 2}, {x / 2, y}, {0, y / 2}};
        Polygon inner{{x / 4, y / 4}, {3 * x / 4, y / 4}, {3 * x / 4, 3 * y / 4}, {x / 4, 3 * y / 4}};
        an.push_back(b.analysis(k, {boundary}, {inner}));
    }
    for (int i = 0; i < n; ++i) {
        int img = *rc::gen::inRange(0, images);
        Blend blend = *rc::gen::element(Blend::alpha, Blend::alpha, Blend::add, Blend::opaque);
        b.add(img, an[std::size_t(img)], *rc::gen::inRange(0, 120), *rc::gen::inRange(0, 120), blend);
        double angle = *rc::gen::inRange(0, 628) / 100.0, scale = *rc::gen::inRange(25, 300) / 100.0;
        auto& t = b.scene.elements.back().transform;
        t[0] = scale * std::cos(angle);
        t[1] = scale * std::sin(angle);
        t[2] = -scale * std::sin(angle);
        t[3] = scale * std::cos(angle);
    }
    return b;
}

RC_GTEST_PROP(SortElements, EveryOrderRespectsEveryEdge, ()) {
    SceneBuilder b = random_scene(*rc::gen::inRange(1, 150), *rc::gen::inRange(1, 6));
    ElementGraph g = build_element_graph(b.scene, b.analyses, GraphMode::polygons);
    for (SortMethod m : {SortMethod::none, SortMethod::paper, SortMethod::batch}) {
        Order order = sort_elements(b.scene, g, m);
        RC_ASSERT(order.size() == b.scene.elements.size());
        std::vector<std::size_t> pos(order.size());
        for (std::size_t p = 0; p < order.size(); ++p) pos[order[p]] = p;
        for (auto [front, back] : edges_of(g)) RC_ASSERT(pos[std::size_t(back)] < pos[std::size_t(front)]);
    }
    RC_ASSERT(count_batches(b.scene, sort_elements(b.scene, g, SortMethod::batch)) <=
              count_batches(b.scene, sort_elements(b.scene, g, SortMethod::paper)));
}

RC_GTEST_PROP(DepthValues, OverlappingElementsNeverShareALevel, ()) {
    SceneBuilder b = random_scene(*rc::gen::inRange(1, 150), *rc::gen::inRange(1, 6));
    ElementGraph g = build_element_graph(b.scene, b.analyses, GraphMode::polygons);
    std::vector<std::int64_t> level = assign_depth_levels(g);
    for (auto [front, back] : edges_of(g)) RC_ASSERT(level[std::size_t(front)] > level[std::size_t(back)]);
}

// The blend pass of the reconstructed meshes draws overlapping elements in
// painter's order: recover each blend vertex's element from its z.
RC_GTEST_PROP(GenerateMeshes, BlendPassKeepsOverlappingPairsInOrder, ()) {
    SceneBuilder b = random_scene(*rc::gen::inRange(1, 100), *rc::gen::inRange(1, 6));
    SceneMeshes m;
    RC_ASSERT(reconstruct_scene(b.scene, b.analyses, {}, &m) == ReconstructStatus::ok);
    bool seen_blend = false;
    for (const Draw& d : m.draws) {
        if (d.pass == Pass::blend) seen_blend = true;
        else RC_ASSERT(!seen_blend); // opaque pass first
        for (std::size_t k = 2; k < d.vertices.size(); k += kVertexFloats) RC_ASSERT(d.vertices[k] > 0.0f && d.vertices[k] <= 1.0f);
    }
    ElementGraph g = build_element_graph(b.scene, b.analyses, GraphMode::polygons);
    RC_ASSERT(m.stats.graph_edges == std::int64_t(g.edge_count()));
}

// A value of the core is a function of its inputs: reconstructing twice
// gives equal values, stats included (they hold no wall time; the callers
// time reconstruction at the edge). Meshes only and its counted stats too.
RC_GTEST_PROP(Reconstruct, TheSameInputGivesEqualValues, ()) {
    SceneBuilder b = random_scene(*rc::gen::inRange(1, 60), *rc::gen::inRange(1, 4));
    SceneMeshes first, second, rects;
    RC_ASSERT(reconstruct_scene(b.scene, b.analyses, {}, &first) == ReconstructStatus::ok);
    RC_ASSERT(reconstruct_scene(b.scene, b.analyses, {}, &second) == ReconstructStatus::ok);
    RC_ASSERT(first.stats == second.stats);
    RC_ASSERT(first.draws.size() == second.draws.size());
    for (std::size_t i = 0; i < first.draws.size(); ++i) {
        RC_ASSERT(first.draws[i].vertices == second.draws[i].vertices);
        RC_ASSERT(first.draws[i].indices == second.draws[i].indices);
    }
    SceneStats counted;
    RC_ASSERT(rectangle_meshes(b.scene, {}, &rects) == ReconstructStatus::ok);
    RC_ASSERT(rectangle_stats(b.scene, {}, &counted) == ReconstructStatus::ok);
    RC_ASSERT(counted == rects.stats);
}

} // namespace
} // namespace depthcull::test
