#include <gtest/gtest.h>

#include "depthcull/geometry.h"
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
