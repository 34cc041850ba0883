// Comparing frames: exact counts on tiny hand-built frames (no GL).
#include <gtest/gtest.h>

#include "depthcull/overdraw.h"
#include "depthcull/render.h"
#include "render_scenes.h"

namespace depthcull {
namespace {


TEST(CompareImages, CountsPixelsAndLargestChannelDifference) {
    Image a = test::ascii_image({"#+", ".#"}), b = a;
    b.rgba[0] += 3;
    b.rgba[4 * 3 + 3] -= 7;
    auto d = render::compare_images(a.view(), b.view());
    EXPECT_EQ(d.pixels_differ, 2);
    EXPECT_EQ(d.max_channel_diff, 7);
    EXPECT_TRUE(d.same_size);
    EXPECT_FALSE(render::compare_images(a.view(), test::ascii_image({"#"}).view()).same_size);
}

} // namespace
} // namespace depthcull

namespace depthcull {
namespace {

TEST(ClassifyDifferences, SeparatesEdgePrecisionFromRealDifferences) {
    // A quad whose right edge runs 0.005 px from the centres of column 4.
    auto m = SceneMeshes{};
    m.viewport = {0, 0, 8, 3};
    Draw d;
    for (Vec2 p : {Vec2{0, 0}, Vec2{4.505, 0}, Vec2{4.505, 3}, Vec2{0, 3}})
        d.vertices.insert(d.vertices.end(), {float(p.x), float(p.y), 0, 0, 0, 1, 1, 1, 1});
    d.indices = {0, 1, 2, 0, 2, 3};
    m.draws.push_back(d);
    Image a = test::ascii_image({"########", "########", "########"}), b = a;
    b.rgba[(1 * 8 + 4) * 4] ^= 1; // on the edge
    b.rgba[(1 * 8 + 2) * 4] ^= 1; // in the middle of the quad
    auto causes = render::classify_differences(a.view(), m, b.view(), m);
    EXPECT_EQ(causes.near_edges, 1);
    EXPECT_EQ(causes.elsewhere, 1);
    EXPECT_EQ(render::classify_differences(a.view(), m, a.view(), m).near_edges, 0);
}

TEST(ClassifyDifferences, TexelEdgesOfTheSceneExplainSamplingTies) {
    // An element 0.002 px off the half-pixel grid: every pixel centre it
    // covers is 0.002 px from a texel edge.
    test::RenderScene rs;
    rs.scene.viewport = {0, 0, 8, 3};
    rs.add_image(test::ascii_image({"####", "####", "####"}), {});
    rs.add(0, {1, 0, 0, 1, 0.502, 0});
    SceneMeshes none;
    none.viewport = rs.scene.viewport;
    Image a = test::ascii_image({"########", "########", "########"}), b = a;
    b.rgba[(1 * 8 + 2) * 4] ^= 1; // inside the element
    b.rgba[(1 * 8 + 6) * 4] ^= 1; // outside it
    auto causes = render::classify_differences(a.view(), none, b.view(), none, &rs.scene);
    EXPECT_EQ(causes.near_edges, 1);
    EXPECT_EQ(causes.elsewhere, 1);
}

} // namespace
} // namespace depthcull
