// add_dynamic_elements derives the static levels from the draws' z values
// (issue 21): a stated stats.depth_levels of INT64_MAX overflowed to z = 0,
// an understated one put the dynamic elements behind the static scene.
#include <cstdint>
#include <limits>

#include <gtest/gtest.h>

#include "scene_fixtures.h"

namespace depthcull::test {
namespace {

float top_z(const SceneMeshes& m, bool dynamic_lowest) {
    float z = dynamic_lowest ? 2.0f : -1.0f;
    for (const Draw& d : m.draws)
        for (std::size_t k = 2; k < d.vertices.size(); k += kVertexFloats) z = dynamic_lowest ? std::min(z, d.vertices[k]) : std::max(z, d.vertices[k]);
    return z;
}

TEST(DynamicLevels, StatedLevelsAreNotTrusted) {
    SceneBuilder b;
    int a = b.image("a", 10, 10);
    b.add(a, b.full_opaque(a), 0, 0);
    b.add(a, b.full_opaque(a), 5, 0);
    b.add(a, b.full_opaque(a), 7, 0);
    ReconstructOptions o;
    o.reserved_dynamic_levels = 4;
    SceneMeshes base;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, o, &base), ReconstructStatus::ok);
    ASSERT_EQ(base.stats.depth_levels, 3);
    EXPECT_EQ(depth_levels_of_draws(base.draws, base.depth_denominator), 3);
    const float static_top = top_z(base, false);
    std::vector<Element> moving{b.scene.elements[0]};
    std::vector<const ImageAnalysis*> an{b.full_opaque(a)};
    for (std::int64_t stated : {std::numeric_limits<std::int64_t>::max(), std::int64_t(0), std::int64_t(1), std::int64_t(3)}) {
        SceneMeshes lying = base, frame;
        lying.stats.depth_levels = stated;
        ASSERT_EQ(add_dynamic_elements(lying, b.scene, moving, an, &frame), ReconstructStatus::ok) << stated;
        EXPECT_GT(top_z(frame, true), static_top) << "stated depth_levels " << stated;
        EXPECT_EQ(frame.stats.depth_levels, 4) << stated;
    }
}

} // namespace
} // namespace depthcull::test
