// Issue 25 point 1: the limit, the cost model's frame time of the ideal
// frame (limit_features): exactly the ideal fragments, blended in one pass,
// one draw per texture, two triangles per element that shows.
#include <cmath>

#include <gtest/gtest.h>

#include "depthcull/cost.h"
#include "depthcull/overdraw.h"

namespace depthcull {
namespace {

Image solid(int w, int h, std::uint8_t alpha) {
    Image img{w, h, std::vector<std::uint8_t>(std::size_t(w) * std::size_t(h) * 4, 200)};
    for (std::size_t i = 3; i < img.rgba.size(); i += 4) img.rgba[i] = alpha;
    return img;
}

TEST(Limit, CountsTheIdealFrameOnly) {
    const Image opaque = solid(8, 8, 255), glass = solid(8, 8, 128);
    Scene scene;
    scene.viewport = {0, 0, 32, 16};
    scene.images = {{"a", "a.png", 8, 8}, {"b", "b.png", 8, 8}};
    auto add = [&](int image, double x, double y, double scale = 1) {
        Element e;
        e.image = image;
        e.rect = {0, 0, 8, 8};
        e.transform = {scale, 0, 0, scale, x, y};
        scene.elements.push_back(e);
    };
    add(0, 0, 0);        // hidden by the next one: not in the ideal frame
    add(0, 0, 0);        // opaque 8x8
    add(1, 4, 0);        // glass over the right half of it and 4 columns past it
    add(1, 20, 4, 0.5);  // glass 4x4, alone
    const std::vector<ImageView> views{opaque.view(), glass.view()};
    const FrameFeatures f = limit_features(scene, views);
    EXPECT_EQ(f.pixels, 32 * 16);
    EXPECT_EQ(f.blend_fragments, 64 + 64 + 16);
    EXPECT_EQ(f.blend_fragments, ideal_overdraw(scene, views).shaded);
    EXPECT_EQ(f.opaque_fragments, 0);
    EXPECT_EQ(f.rejected_fragments, 0);
    EXPECT_FALSE(f.depth_clear);
    EXPECT_EQ(f.draw_calls, 2); // two textures
    EXPECT_EQ(f.texture_switches, 2);
    EXPECT_EQ(f.triangles, 6);  // three elements show
    // Two squares of side 8 and one of 4, each an outline and a diagonal twice.
    const double d = std::sqrt(2.0);
    EXPECT_NEAR(f.triangle_perimeter, 2 * (32 + 16 * d) + (16 + 8 * d), 1e-9);
    CostProfile p;
    builtin_profile("llvmpipe", &p);
    EXPECT_DOUBLE_EQ(limit_ms(p, scene, views), predict_ms(p, f));
}

TEST(Limit, ClipsThePerimeterToTheViewport) {
    const Image opaque = solid(8, 8, 255);
    Scene scene;
    scene.viewport = {0, 0, 4, 4};
    scene.images = {{"a", "a.png", 8, 8}};
    Element e;
    e.rect = {0, 0, 8, 8};
    scene.elements.push_back(e);
    const FrameFeatures f = limit_features(scene, {opaque.view()});
    EXPECT_EQ(f.blend_fragments, 16);
    EXPECT_NEAR(f.triangle_perimeter, 16 + 8 * std::sqrt(2.0), 1e-9);
}

} // namespace
} // namespace depthcull
