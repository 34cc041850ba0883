// Paper 2.3: the element graph, exact expected edges on small scenes, and
// the grid against an all-pairs oracle on random axis-aligned scenes.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "scene_fixtures.h"

namespace depthcull::test {
namespace {

using Edges = std::vector<std::pair<int, int>>;

TEST(ElementGraph, OverlapAndTouchingMakeEdgesSeparationDoesNot) {
    SceneBuilder b;
    int sq = b.image("sq", 10, 10);
    const ImageAnalysis* a = b.full(sq);
    b.add(sq, a, 0, 0);    // 0
    b.add(sq, a, 5, 5);    // 1 overlaps 0
    b.add(sq, a, 15, 0);   // 2 touches 1 (x = 15 edge)
    b.add(sq, a, 25.5, 0); // 3 half a pixel from 2: separate
    b.add(sq, a, 100, 100);
    ElementGraph g = build_element_graph(b.scene, b.analyses, GraphMode::polygons);
    EXPECT_EQ(edges_of(g), (Edges{{1, 0}, {2, 1}}));
    EXPECT_TRUE(g.has_edge(1, 0));
    EXPECT_FALSE(g.has_edge(0, 1));
    EXPECT_FALSE(g.has_edge(3, 2));
}

TEST(ElementGraph, PolygonsSeeThroughTransparentCornersBoxesDoNot) {
    // Two diamonds whose boxes overlap at a corner but whose boundary
    // polygons are far apart.
    SceneBuilder b;
    int d = b.image("diamond", 20, 20);
    const ImageAnalysis* a = b.analysis(d, {{{10, 0}, {20, 10}, {10, 20}, {0, 10}}});
    b.add(d, a, 0, 0);
    b.add(d, a, 16, 16);
    EXPECT_EQ(edges_of(build_element_graph(b.scene, b.analyses, GraphMode::polygons)), Edges{});
    EXPECT_EQ(edges_of(build_element_graph(b.scene, b.analyses, GraphMode::boxes)), (Edges{{1, 0}}));
}

TEST(ElementGraph, NonConvexPolygonsUseTheExactTest) {
    // An L shape and a square in its notch: the hulls overlap, the shapes
    // do not.
    SceneBuilder b;
    int l = b.image("L", 20, 20);
    int s = b.image("s", 6, 6);
    const ImageAnalysis* la = b.analysis(l, {{{0, 0}, {8, 0}, {8, 12}, {20, 12}, {20, 20}, {0, 20}}});
    b.add(l, la, 0, 0);
    b.add(s, b.full(s), 11, 3); // in the notch, 3 px from both arms
    b.add(s, b.full(s), 7, 3);  // overlaps the vertical arm
    EXPECT_EQ(edges_of(build_element_graph(b.scene, b.analyses, GraphMode::polygons)), (Edges{{2, 0}, {2, 1}}));
}

TEST(ElementGraph, RotationAndMirroring) {
    SceneBuilder b;
    int sq = b.image("sq", 10, 10);
    const ImageAnalysis* a = b.full(sq);
    b.add(sq, a, 0, 0);
    // Rotated 45 degrees about its top-left, placed so its left corner is
    // 1 px right of the first square: no overlap.
    b.add(sq, a, 0, 0);
    const double c = std::sqrt(0.5);
    b.scene.elements[1].transform = {c, c, -c, c, 11 + 10 * c, 0};
    // Mirrored horizontally (negative scale) overlapping the first.
    b.add(sq, a, 0, 0);
    b.scene.elements[2].transform = {-1, 0, 0, 1, 10, 2};
    EXPECT_EQ(edges_of(build_element_graph(b.scene, b.analyses, GraphMode::polygons)), (Edges{{2, 0}}));
}

TEST(ElementGraph, ElementsThatDrawNothingHaveNoEdges) {
    SceneBuilder b;
    int sq = b.image("sq", 10, 10);
    const ImageAnalysis* empty = b.analysis(sq, {});
    b.add(sq, b.full(sq), 0, 0);
    b.add(sq, empty, 0, 0);
    b.add(sq, b.full(sq), 0, 0, Blend::alpha, 0.0f); // colour alpha 0 changes nothing
    b.add(sq, b.full(sq), 2, 2);
    EXPECT_EQ(edges_of(build_element_graph(b.scene, b.analyses, GraphMode::polygons)), (Edges{{3, 0}}));
}

// Axis-aligned integer rects: closed boxes overlap exactly when the
// intervals do, an oracle the grid must match edge for edge.
RC_GTEST_PROP(ElementGraph, GridMatchesAllPairsOnAxisAlignedScenes, ()) {
    SceneBuilder b;
    const int n = *rc::gen::inRange(1, 120);
    const int images = *rc::gen::inRange(1, 6);
    for (int k = 0; k < images; ++k) b.image("i" + std::to_string(k), *rc::gen::inRange(1, 40), *rc::gen::inRange(1, 40));
    std::vector<const ImageAnalysis*> full;
    for (int k = 0; k < images; ++k) full.push_back(b.full(k));
    const int world = *rc::gen::inRange(10, 400);
    for (int i = 0; i < n; ++i) {
        int img = *rc::gen::inRange(0, images);
        b.add(img, full[std::size_t(img)], *rc::gen::inRange(0, world), *rc::gen::inRange(0, world));
        double s = *rc::gen::element(0.5, 1.0, 2.0);
        b.scene.elements.back().transform[0] = s;
        b.scene.elements.back().transform[3] = s;
    }
    ElementGraph g = build_element_graph(b.scene, b.analyses, GraphMode::polygons);
    Edges expected;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < i; ++j) {
            auto box = [&](int e) {
                const Element& el = b.scene.elements[std::size_t(e)];
                return Box{el.transform[4], el.transform[5], el.transform[4] + el.transform[0] * el.rect.w,
                           el.transform[5] + el.transform[3] * el.rect.h};
            };
            Box p = box(i), q = box(j);
            if (p.x0 <= q.x1 && q.x0 <= p.x1 && p.y0 <= q.y1 && q.y0 <= p.y1) expected.push_back({i, j});
        }
    }
    RC_ASSERT(edges_of(g) == expected);
}

} // namespace
} // namespace depthcull::test
