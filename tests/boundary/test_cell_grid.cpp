// The sound IsLineEmpty (paper 2.1.1 and errata) on the cell grid: a
// segment may follow the texels' outline but not pass between two texels
// that share a side, nor through any texel's interior.
#include <gtest/gtest.h>

#include "boundary/boundary_internal.h"
#include "testing/ascii_image.h"

using namespace depthcull;
using namespace depthcull::boundary;
using depthcull::test::ascii_image;

namespace {

CellGrid grid_of(const std::vector<std::string>& rows, Filter f = Filter::nearest) {
    static std::vector<Image> keep; // the grid copies runs, but keep views valid anyway
    keep.push_back(ascii_image(rows));
    return make_cell_grid(keep.back().view(), keep.back().view().bounds(), f);
}

} // namespace

TEST(CellGrid, RunsAndBox) {
    CellGrid g = grid_of({"....", ".##.", "...#"});
    EXPECT_EQ(g.cells(), 3);
    EXPECT_TRUE(g.occupied(1, 1));
    EXPECT_FALSE(g.occupied(0, 1));
    Bounds b = g.box();
    EXPECT_EQ(b.x0, 1);
    EXPECT_EQ(b.y0, 1);
    EXPECT_EQ(b.x1, 4);
    EXPECT_EQ(b.y1, 3);
}

TEST(CellGrid, SegmentsAlongTheOutlineAreClear) {
    CellGrid g = grid_of({"....", ".##.", ".##.", "...."});
    EXPECT_TRUE(g.segment_clear({1, 1}, {3, 1})); // top side
    EXPECT_TRUE(g.segment_clear({3, 1}, {3, 3})); // right side
    EXPECT_FALSE(g.segment_clear({0, 0}, {4, 4})); // the diagonal crosses the texels
    EXPECT_FALSE(g.segment_clear({1, 2}, {2, 1})); // cuts texel (1,1)
    EXPECT_TRUE(g.segment_clear({0, 2}, {1, 1}));          // outside, touching the corner
}

TEST(CellGrid, SegmentsBetweenTexelsSharingASideAreNotClear) {
    CellGrid g = grid_of({"##", "##"});
    EXPECT_FALSE(g.segment_clear({1, 0}, {1, 2})); // between columns
    EXPECT_FALSE(g.segment_clear({0, 1}, {2, 1})); // between rows
    CellGrid diagonal = grid_of({"#.", ".#"});
    // Through the corner shared by two diagonal texels: separates them but
    // enters neither, so it is clear.
    EXPECT_TRUE(diagonal.segment_clear({0, 2}, {2, 0}));
    EXPECT_TRUE(diagonal.segment_clear({1, 0}, {1, 2}));
}

TEST(CellGrid, LinearGrowsByHalfATexelOnTheDoubledGrid) {
    CellGrid g = grid_of({"...", ".#.", "..."}, Filter::linear);
    EXPECT_EQ(g.width(), 6);
    EXPECT_EQ(g.cells(), 16); // texels [0.5, 2.5)^2 = half-texel cells [1, 5)^2
    Bounds b = g.box();
    EXPECT_EQ(b.x0, 1);
    EXPECT_EQ(b.x1, 5);
    CellGrid corner = grid_of({"#.", ".."}, Filter::linear);
    EXPECT_EQ(corner.cells(), 9); // clipped to the rect: [0, 1.5)^2
}

TEST(CellGrid, FloorAndCeilDivisionRoundTowardInfinities) {
    EXPECT_EQ(floor_div(-7, 2), -4);
    EXPECT_EQ(floor_div(7, 2), 3);
    EXPECT_EQ(floor_div(7, -2), -4);
    EXPECT_EQ(ceil_div(-7, 2), -3);
    EXPECT_EQ(ceil_div(7, 2), 4);
    EXPECT_EQ(floor_div(-6, 3), -2);
}
