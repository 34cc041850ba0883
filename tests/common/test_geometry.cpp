#include <gtest/gtest.h>

#include "depthcull/geometry.h"
#include "common/segments.h"
#include "testing/ascii_image.h"

using namespace depthcull;

TEST(Geometry, AreaIsPositiveForClockwiseYDown) {
    Polygon square{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
    EXPECT_EQ(signed_area(square), 4.0);
    Polygon ccw{{0, 0}, {0, 2}, {2, 2}, {2, 0}};
    EXPECT_EQ(signed_area(ccw), -4.0);
    EXPECT_EQ(area(ccw), 4.0);
}

TEST(Geometry, SimpleAndConvex) {
    EXPECT_TRUE(is_simple({{0, 0}, {2, 0}, {2, 2}, {0, 2}}));
    EXPECT_TRUE(is_convex({{0, 0}, {2, 0}, {2, 2}, {0, 2}}));
    EXPECT_FALSE(is_simple({{0, 0}, {2, 2}, {2, 0}, {0, 2}})); // bow tie
    Polygon l{{0, 0}, {1, 0}, {1, 1}, {2, 1}, {2, 2}, {0, 2}};
    EXPECT_TRUE(is_simple(l));
    EXPECT_FALSE(is_convex(l));
    EXPECT_FALSE(is_simple({{0, 0}, {2, 0}, {1, 0}, {1, 1}})); // folds back on itself
    EXPECT_TRUE(is_simple({{0, 0}, {1, 0}, {2, 0}, {2, 2}}));  // collinear vertex is fine
}

TEST(Image, MasksAndAsciiRoundTrip) {
    std::vector<std::string> rows{"..#", ".+#", "###"};
    Image img = test::ascii_image(rows);
    EXPECT_EQ(test::ascii_rows(img.view()), rows);
    Mask nt = nontransparent_mask(img.view(), {1, 1, 2, 2});
    Mask op = opaque_mask(img.view(), {1, 1, 2, 2});
    EXPECT_TRUE(nt.at(0, 0));
    EXPECT_FALSE(op.at(0, 0));
    EXPECT_TRUE(op.at(1, 0));
    EXPECT_TRUE(nontransparent_mask(img.view(), {2, 2, 2, 2}).bits.empty()); // outside the image
}

// The one segment-touch test behind both is_simple predicates (boundary's
// integer one and geometry's double one): closed segments, so touching at
// an end or overlapping along a line counts.
TEST(Geometry, SegmentsTouchCountsEndsAndCollinearOverlaps) {
    auto touch = [](Vec2 a, Vec2 b, Vec2 c, Vec2 d) { return segments_touch(a, b, c, d); };
    EXPECT_TRUE(touch({0, 0}, {2, 2}, {0, 2}, {2, 0}));     // proper crossing
    EXPECT_TRUE(touch({0, 0}, {2, 0}, {1, 0}, {1, 3}));     // T: an end on the other
    EXPECT_TRUE(touch({0, 0}, {1, 1}, {1, 1}, {3, 0}));     // shared end
    EXPECT_TRUE(touch({0, 0}, {3, 0}, {2, 0}, {5, 0}));     // collinear overlap
    EXPECT_TRUE(touch({0, 0}, {0.5, 0}, {0.5, 0}, {1, 0})); // halves are exact
    EXPECT_FALSE(touch({0, 0}, {1, 0}, {2, 0}, {3, 0}));    // collinear, apart
    EXPECT_FALSE(touch({0, 0}, {2, 0}, {0, 1}, {2, 1}));    // parallel
    EXPECT_FALSE(touch({0, 0}, {2, 0}, {1, 1}, {1, 0.5}));  // stops short
    EXPECT_FALSE(touch({0, 0}, {2, 2}, {3, 0}, {2, 1}));    // lines cross outside
}
