// Paper 2.3.3 AddPolygon: ear clipping. Metrics, not golden meshes: the
// triangles' areas add up to the polygon's exactly (texel-grid vertices),
// every triangle has the polygon's orientation, and none reaches outside.
#include <cmath>

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "depthcull/scene.h"

namespace depthcull {
namespace {

// Exact for grid points: twice the area, summed.
double twice_area_of_triangles(const Polygon& p, const std::vector<std::uint32_t>& t) {
    double sum = 0;
    for (std::size_t k = 0; k < t.size(); k += 3) sum += orient(p[t[k]], p[t[k + 1]], p[t[k + 2]]);
    return sum;
}

bool point_inside(const Polygon& poly, Vec2 p) {
    bool inside = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        if ((poly[i].y > p.y) != (poly[j].y > p.y)) {
            double x = poly[j].x + (p.y - poly[j].y) * (poly[i].x - poly[j].x) / (poly[i].y - poly[j].y);
            if (p.x < x) inside = !inside;
        }
    }
    return inside;
}

void check_triangulation(const Polygon& p) {
    std::vector<std::uint32_t> t = triangulate_polygon(p);
    ASSERT_EQ(t.size() % 3, 0u);
    EXPECT_EQ(twice_area_of_triangles(p, t), 2 * signed_area(p));
    const double sign = signed_area(p) > 0 ? 1 : -1;
    for (std::size_t k = 0; k < t.size(); k += 3) {
        Vec2 a = p[t[k]], b = p[t[k + 1]], c = p[t[k + 2]];
        EXPECT_GT(sign * orient(a, b, c), 0);
        EXPECT_TRUE(point_inside(p, {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3}));
    }
}

TEST(Triangulate, ConvexAndConcave) {
    check_triangulation({{0, 0}, {4, 0}, {4, 4}, {0, 4}});
    EXPECT_EQ(triangulate_polygon({{0, 0}, {4, 0}, {4, 4}, {0, 4}}).size(), 6u);
    check_triangulation({{0, 0}, {8, 0}, {8, 12}, {20, 12}, {20, 20}, {0, 20}});               // L
    check_triangulation({{0, 0}, {2, 0}, {2, 5}, {3, 5}, {3, 0}, {5, 0}, {5, 8}, {0, 8}});     // comb
    check_triangulation({{0, 4}, {3, 3}, {4, 0}, {5, 3}, {8, 4}, {5, 5}, {4, 8}, {3, 5}});      // star
    check_triangulation({{0, 0}, {4, 0}, {4, 4}, {0, 4}, {2, 2}}); // arrow: reflex vertex at the centre
}

TEST(Triangulate, CollinearVertices) {
    // Midpoints on every edge, and a run of collinear vertices.
    check_triangulation({{0, 0}, {2, 0}, {4, 0}, {4, 2}, {4, 4}, {2, 4}, {0, 4}, {0, 2}});
    check_triangulation({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {2, 3}});
    // A reflex vertex whose diagonal would pass through another vertex.
    check_triangulation({{0, 0}, {6, 0}, {6, 6}, {3, 3}, {0, 6}});
    check_triangulation({{0, 0}, {6, 0}, {6, 2}, {3, 2}, {3, 4}, {6, 4}, {6, 6}, {0, 6}, {0, 4}, {0, 2}});
    // Half-texel vertices (linear filtering pulls polygons by halves).
    check_triangulation({{0.5, 0}, {3.5, 0}, {4, 0.5}, {4, 3.5}, {3.5, 4}, {0.5, 4}, {0, 3.5}, {0, 0.5}});
}

TEST(Triangulate, EitherOrientationAndDegenerate) {
    check_triangulation({{0, 4}, {4, 4}, {4, 0}, {0, 0}}); // counter-clockwise
    EXPECT_TRUE(triangulate_polygon({{0, 0}, {1, 1}}).empty());
    EXPECT_TRUE(triangulate_polygon({{0, 0}, {1, 1}, {2, 2}}).empty()); // zero area
}

// Random star-shaped polygons on the integer grid (collinear vertices and
// all), kept when simple.
RC_GTEST_PROP(Triangulate, AreaIsPreservedExactly, ()) {
    const int n = *rc::gen::inRange(3, 16);
    std::vector<int> angles = *rc::gen::container<std::vector<int>>(std::size_t(n), rc::gen::inRange(0, 3600));
    std::sort(angles.begin(), angles.end());
    angles.erase(std::unique(angles.begin(), angles.end()), angles.end());
    Polygon p;
    for (int a : angles) {
        double r = *rc::gen::inRange(1, 20);
        double t = a / 3600.0 * 2 * M_PI;
        Vec2 v{std::round(20 + r * std::cos(t)), std::round(20 + r * std::sin(t))};
        if (p.empty() || !(p.back() == v)) p.push_back(v);
    }
    while (p.size() > 1 && p.front() == p.back()) p.pop_back();
    RC_PRE(p.size() >= 3 && is_simple(p) && signed_area(p) != 0);
    std::vector<std::uint32_t> t = triangulate_polygon(p);
    RC_ASSERT(twice_area_of_triangles(p, t) == 2 * signed_area(p));
    const double sign = signed_area(p) > 0 ? 1 : -1;
    for (std::size_t k = 0; k < t.size(); k += 3) {
        Vec2 a = p[t[k]], b = p[t[k + 1]], c = p[t[k + 2]];
        RC_ASSERT(sign * orient(a, b, c) > 0);
        RC_ASSERT(point_inside(p, {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3}));
    }
}

} // namespace
} // namespace depthcull
