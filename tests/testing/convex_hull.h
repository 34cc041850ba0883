// The convex hull of points (Andrew's monotone chain) for tests that need
// random convex polygons; no straight angles. P has x and y; cross(o, a, b)
// is exact for P's coordinates. The library's own hull (src/boundary)
// works on occupied cells, not points.
#pragma once

#include <algorithm>
#include <vector>

namespace depthcull::test {

// Counter-clockwise in y-up terms (clockwise on screen, y down).
template <class P, class Cross>
std::vector<P> convex_hull(std::vector<P> points, Cross cross) {
    std::sort(points.begin(), points.end(), [](const P& a, const P& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
    std::vector<P> hull;
    for (int pass = 0; pass < 2; ++pass) {
        const std::size_t start = hull.size();
        for (const P& q : points) {
            while (hull.size() >= start + 2 && cross(hull[hull.size() - 2], hull.back(), q) <= 0) hull.pop_back();
            hull.push_back(q);
        }
        hull.pop_back();
        std::reverse(points.begin(), points.end());
    }
    return hull;
}

} // namespace depthcull::test
