// Hand-made images with exact expectations (paper 2.1 and beyond).
#include <gtest/gtest.h>

#include "boundary_checks.h"

using namespace depthcull;
using depthcull::test::ascii_image;

TEST(Boundary, FullyTransparentGivesNoPolygon) {
    Image img = ascii_image({"...", "...", "..."});
    EXPECT_TRUE(test::boundary_polygons(img.view(), img.view().bounds(), {}).empty());
    test::FilteredBoundary linear;
    linear.filter = Filter::linear;
    EXPECT_TRUE(test::boundary_polygons(img.view(), img.view().bounds(), linear).empty());
    EXPECT_TRUE(test::boundary_polygons(img.view(), Rect{1, 1, 0, 0}, {}).empty());
}

TEST(Boundary, OnePixelImage) {
    Image img = ascii_image({"#"});
    auto polys = test::boundary_polygons(img.view(), img.view().bounds(), {});
    ASSERT_EQ(polys.size(), 1u);
    EXPECT_EQ(polys[0], (Polygon{{0, 0}, {1, 0}, {1, 1}, {0, 1}}));
    // Linear: the grown square clipped to the 1x1 rect is the same square.
    test::FilteredBoundary linear;
    linear.filter = Filter::linear;
    polys = test::boundary_polygons(img.view(), img.view().bounds(), linear);
    ASSERT_EQ(polys.size(), 1u);
    EXPECT_EQ(area(polys[0]), 1.0);
    test::expect_boundary_guarantees(img.view(), img.view().bounds(), polys, linear);
}

TEST(Boundary, OnePixelInsideLargerImage) {
    Image img = ascii_image({".....", ".....", "..+..", ".....", "....."});
    auto polys = test::boundary_polygons(img.view(), img.view().bounds(), {});
    ASSERT_EQ(polys.size(), 1u);
    EXPECT_EQ(polys[0], (Polygon{{2, 2}, {3, 2}, {3, 3}, {2, 3}}));
    test::FilteredBoundary linear;
    linear.filter = Filter::linear;
    polys = test::boundary_polygons(img.view(), img.view().bounds(), linear);
    ASSERT_EQ(polys.size(), 1u);
    EXPECT_EQ(polys[0], (Polygon{{1.5, 1.5}, {3.5, 1.5}, {3.5, 3.5}, {1.5, 3.5}}));
}

// The paper's Figures 1a-1d: an L shape is fitted exactly.
TEST(Boundary, PaperLShapeFitsExactly) {
    Image img = ascii_image({
        "##....",
        "##....",
        "##....",
        "######",
        "######",
    });
    auto polys = test::boundary_polygons(img.view(), img.view().bounds(), {});
    ASSERT_EQ(polys.size(), 1u);
    EXPECT_EQ(area(polys[0]), 18.0); // the texel count: a perfect fit
    EXPECT_EQ(polys[0].size(), 6u);
    test::expect_boundary_guarantees(img.view(), img.view().bounds(), polys, {});
}

TEST(Boundary, DiagonalStaircase) {
    Image img = ascii_image({
        "#.......",
        "##......",
        "###.....",
        "####....",
        "#####...",
        "######..",
        "#######.",
        "########",
    });
    auto polys = test::boundary_polygons(img.view(), img.view().bounds(), {});
    ASSERT_EQ(polys.size(), 1u);
    // The staircase's outer hull is the triangle (0,0) (8,7)... cut to the
    // grid: a triangle plus the stair tips, far below the box's 64.
    EXPECT_LE(area(polys[0]), 40.0);
    EXPECT_GE(area(polys[0]), 36.0);
    test::expect_boundary_guarantees(img.view(), img.view().bounds(), polys, {});
}

TEST(Boundary, ContentTouchingEveryEdgeStaysInRect) {
    Image img = ascii_image({
        "...##...",
        "..####..",
        ".######.",
        "########",
        ".######.",
        "..####..",
        "...##...",
    });
    for (Filter f : {Filter::nearest, Filter::linear}) {
        test::FilteredBoundary o;
        o.filter = f;
        auto polys = test::boundary_polygons(img.view(), img.view().bounds(), o);
        ASSERT_EQ(polys.size(), 1u);
        test::expect_boundary_guarantees(img.view(), img.view().bounds(), polys, o);
        EXPECT_LT(area(polys[0]), 56.0 * 0.85); // corners cut off the 8x7 rect
    }
}

TEST(Boundary, CircleIsFittedTightly) {
    std::vector<std::string> rows;
    for (int y = 0; y < 32; ++y) {
        std::string r;
        for (int x = 0; x < 32; ++x) r += (x - 15.5) * (x - 15.5) + (y - 15.5) * (y - 15.5) < 15.0 * 15.0 ? '#' : '.';
        rows.push_back(r);
    }
    Image img = ascii_image(rows);
    std::int64_t texels = 0;
    for (auto& r : rows) texels += std::count(r.begin(), r.end(), '#');
    auto polys = test::boundary_polygons(img.view(), img.view().bounds(), {});
    ASSERT_EQ(polys.size(), 1u);
    EXPECT_LE(polys[0].size(), 10u);
    test::expect_boundary_guarantees(img.view(), img.view().bounds(), polys, {});
    // A regular 10-gon around a circle covers ~1.034x its area; the box 1.27x.
    EXPECT_LT(area(polys[0]) / double(texels), 1.12);
}

TEST(Boundary, RingKeepsItsHoleInside) {
    std::vector<std::string> rows;
    for (int y = 0; y < 24; ++y) {
        std::string r;
        for (int x = 0; x < 24; ++x) {
            double d = (x - 11.5) * (x - 11.5) + (y - 11.5) * (y - 11.5);
            r += d < 11.0 * 11.0 && d > 6.0 * 6.0 ? '#' : '.';
        }
        rows.push_back(r);
    }
    Image img = ascii_image(rows);
    for (Filter f : {Filter::nearest, Filter::linear}) {
        test::FilteredBoundary o;
        o.filter = f;
        auto polys = test::boundary_polygons(img.view(), img.view().bounds(), o);
        ASSERT_EQ(polys.size(), 1u); // one island: a simple polygon cannot exclude the hole
        test::expect_boundary_guarantees(img.view(), img.view().bounds(), polys, o);
    }
}

TEST(Boundary, TwoIslandsGetTwoPolygons) {
    std::vector<std::string> rows;
    for (int y = 0; y < 16; ++y) {
        std::string r;
        for (int x = 0; x < 48; ++x) {
            double d1 = (x - 7.5) * (x - 7.5) + (y - 7.5) * (y - 7.5);
            double d2 = (x - 40.5) * (x - 40.5) + (y - 7.5) * (y - 7.5);
            r += d1 < 7.0 * 7.0 || d2 < 7.0 * 7.0 ? '#' : '.';
        }
        rows.push_back(r);
    }
    Image img = ascii_image(rows);
    for (Filter f : {Filter::nearest, Filter::linear}) {
        test::FilteredBoundary o;
        o.filter = f;
        auto polys = test::boundary_polygons(img.view(), img.view().bounds(), o);
        ASSERT_EQ(polys.size(), 2u);
        test::expect_boundary_guarantees(img.view(), img.view().bounds(), polys, o);
        o.split_parts = false;
        auto one = test::boundary_polygons(img.view(), img.view().bounds(), o);
        ASSERT_EQ(one.size(), 1u);
        test::expect_boundary_guarantees(img.view(), img.view().bounds(), one, o);
        EXPECT_LT(total_area(polys), 0.7 * total_area(one));
    }
}

TEST(Boundary, SubRectUsesFullImageCoordinates) {
    Image img = ascii_image({
        "########",
        "#......#",
        "#..#...#",
        "#......#",
        "########",
    });
    Rect r{2, 1, 4, 3};
    auto polys = test::boundary_polygons(img.view(), r, {});
    ASSERT_EQ(polys.size(), 1u);
    EXPECT_EQ(polys[0], (Polygon{{3, 2}, {4, 2}, {4, 3}, {3, 3}}));
    test::FilteredBoundary linear;
    linear.filter = Filter::linear;
    polys = test::boundary_polygons(img.view(), r, linear);
    test::expect_boundary_guarantees(img.view(), r, polys, linear);
    EXPECT_EQ(polys[0], (Polygon{{2.5, 1.5}, {4.5, 1.5}, {4.5, 3.5}, {2.5, 3.5}}));
}

TEST(Boundary, MaxVerticesIsRespected) {
    std::vector<std::string> rows;
    for (int y = 0; y < 40; ++y) {
        std::string r;
        for (int x = 0; x < 40; ++x) r += (x - 19.5) * (x - 19.5) + (y - 19.5) * (y - 19.5) < 19.0 * 19.0 ? '#' : '.';
        rows.push_back(r);
    }
    Image img = ascii_image(rows);
    double previous = 1e9;
    for (int m : {4, 5, 6, 8, 10, 16}) {
        test::FilteredBoundary o;
        o.max_vertices = m;
        auto polys = test::boundary_polygons(img.view(), img.view().bounds(), o);
        ASSERT_EQ(polys.size(), 1u);
        EXPECT_LE(int(polys[0].size()), m);
        test::expect_boundary_guarantees(img.view(), img.view().bounds(), polys, o);
        EXPECT_LE(area(polys[0]), previous * 1.02) << m; // more vertices: no worse (greedy, so roughly)
        previous = std::min(previous, area(polys[0]));
    }
}

TEST(Boundary, ManyIslandsGiveFewPolygons) {
    // A 5x4 grid of 4x4 squares: twenty islands, at most four polygons
    // (each costs triangles), all disjoint, everything contained.
    std::vector<std::string> rows(40, std::string(50, '.'));
    for (int gy = 0; gy < 4; ++gy)
        for (int gx = 0; gx < 5; ++gx)
            for (int y = 0; y < 4; ++y)
                for (int x = 0; x < 4; ++x) rows[std::size_t(gy * 10 + 3 + y)][std::size_t(gx * 10 + 3 + x)] = '#';
    Image img = ascii_image(rows);
    for (Filter f : {Filter::nearest, Filter::linear}) {
        test::FilteredBoundary o;
        o.filter = f;
        auto polys = test::boundary_polygons(img.view(), img.view().bounds(), o);
        EXPECT_GE(polys.size(), 1u);
        EXPECT_LE(polys.size(), 4u);
        test::expect_boundary_guarantees(img.view(), img.view().bounds(), polys, o);
    }
}

TEST(Boundary, DeterministicOutput) {
    Image img = ascii_image({"..##....#", ".####..##", "######.##", ".####....", "..#......"});
    test::FilteredBoundary o;
    auto a = test::boundary_polygons(img.view(), img.view().bounds(), o);
    auto b = test::boundary_polygons(img.view(), img.view().bounds(), o);
    EXPECT_EQ(a, b);
}
