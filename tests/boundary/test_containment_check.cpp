// count_uncontained_texels is the exact judge of the boundary guarantee; it
// is tested on its own with hand-made polygons and exact counts.
#include <gtest/gtest.h>

#include "depthcull/analyze.h"
#include "testing/ascii_image.h"

using namespace depthcull;
using depthcull::test::ascii_image;

namespace {

const Image& plus_image() {
    static const Image img = ascii_image({
        ".....",
        "..#..",
        ".###.",
        "..#..",
        ".....",
    });
    return img;
}

std::int64_t uncontained(const std::vector<Polygon>& polys, Filter f = Filter::nearest) {
    return count_uncontained_texels(plus_image().view(), plus_image().view().bounds(), polys, f);
}

} // namespace

TEST(ContainmentCheck, NoPolygonLeavesEveryTexelOut) { EXPECT_EQ(uncontained({}), 5); }

TEST(ContainmentCheck, BoxAndTightPolygonContainAll) {
    EXPECT_EQ(uncontained({{{1, 1}, {4, 1}, {4, 4}, {1, 4}}}), 0);
    // The plus itself, traced along texel edges: touching is inside.
    Polygon plus{{2, 1}, {3, 1}, {3, 2}, {4, 2}, {4, 3}, {3, 3}, {3, 4}, {2, 4}, {2, 3}, {1, 3}, {1, 2}, {2, 2}};
    EXPECT_EQ(uncontained({plus}), 0);
    // The diamond through the arms' outer corners also contains them.
    EXPECT_EQ(uncontained({{{2, 1}, {3, 1}, {4, 2}, {4, 3}, {3, 4}, {2, 4}, {1, 3}, {1, 2}}}), 0);
}

TEST(ContainmentCheck, EdgeThroughASquareCounts) {
    // The diagonal from (1,2) to (3,1) cuts through the top arm's texel
    // (2,1) (y = 1.5 at x = 2); it passes above texel (1,2), which it only
    // touches at the corner (1,2).
    EXPECT_EQ(uncontained({{{1, 2}, {3, 1}, {4, 2}, {4, 3}, {3, 4}, {2, 4}, {1, 3}}}), 1);
    // A box one texel short on the right loses the right arm.
    EXPECT_EQ(uncontained({{{1, 1}, {3, 1}, {3, 4}, {1, 4}}}), 1);
    // Cutting through the middle of the right arm square at x = 3.5.
    EXPECT_EQ(uncontained({{{1, 1}, {3.5, 1}, {3.5, 4}, {1, 4}}}), 1);
}

TEST(ContainmentCheck, SquareMustBeInsideOnePolygon) {
    // Two polygons meeting along x = 2.5 split the centre column: its three
    // texels are in neither polygon alone.
    Polygon left{{1, 1}, {2.5, 1}, {2.5, 4}, {1, 4}}, right{{2.5, 1}, {4, 1}, {4, 4}, {2.5, 4}};
    EXPECT_EQ(uncontained({left, right}), 3);
    // Counter-clockwise input is judged by the region it encloses.
    EXPECT_EQ(uncontained({{{1, 1}, {1, 4}, {4, 4}, {4, 1}}}), 0);
}

TEST(ContainmentCheck, LinearGrowsSquaresByHalfATexel) {
    Polygon box{{1, 1}, {4, 1}, {4, 4}, {1, 4}};
    // Only the centre texel's grown square [1.5, 3.5]^2 fits in the box.
    EXPECT_EQ(uncontained({box}, Filter::linear), 4);
    Polygon grown{{0.5, 0.5}, {4.5, 0.5}, {4.5, 4.5}, {0.5, 4.5}};
    EXPECT_EQ(uncontained({grown}, Filter::linear), 0);
    // Clipped to the rect: a texel on the image border needs no room outside.
    Image edge = ascii_image({"#.", ".."});
    EXPECT_EQ(count_uncontained_texels(edge.view(), edge.view().bounds(), {{{0, 0}, {1.5, 0}, {1.5, 1.5}, {0, 1.5}}},
                                       Filter::linear),
              0);
    EXPECT_EQ(count_uncontained_texels(edge.view(), edge.view().bounds(), {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}},
                                       Filter::linear),
              1);
}

TEST(ContainmentCheck, SubRectCountsOnlyItsTexels) {
    // Rect covering the plus's top arm only.
    EXPECT_EQ(count_uncontained_texels(plus_image().view(), Rect{2, 0, 1, 2}, {}, Filter::nearest), 1);
    EXPECT_EQ(count_uncontained_texels(plus_image().view(), Rect{2, 0, 1, 2}, {{{2, 1}, {3, 1}, {3, 2}, {2, 2}}},
                                       Filter::nearest),
              0);
}

TEST(ContainmentCheck, NonDyadicCoordinatesContainNothing) {
    // 1/3 is not exact in binary: the checker refuses to guess.
    Polygon thirds{{1.0 / 3, 1.0 / 3}, {4.5, 1.0 / 3}, {4.5, 4.5}, {1.0 / 3, 4.5}};
    EXPECT_EQ(uncontained({thirds}), 5);
}
