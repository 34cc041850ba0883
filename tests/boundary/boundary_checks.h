// Shared checks of the boundary polygon guarantees (paper 2.1 and the
// issue's items 3-5), used by the hand-made, property and corpus tests.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthcull/analyze.h"
#include "depthcull/geometry.h"
#include "testing/ascii_image.h"

namespace depthcull::test {

// BoundaryOptions and the filter the polygons are made for (in a real
// analysis AnalyzeOptions::filter), kept together for the tests.
struct FilteredBoundary : BoundaryOptions {
    Filter filter = Filter::nearest;
};
inline std::vector<Polygon> boundary_polygons(ImageView image, Rect rect, const FilteredBoundary& options) {
    return generate_boundary_polygons(image, rect, options, options.filter);
}

// Empty when the guarantees hold, else what is wrong (for RC_ASSERT and
// EXPECT alike).
std::string boundary_guarantee_failure(ImageView image, Rect rect, const std::vector<Polygon>& polygons,
                                       const FilteredBoundary& options);

inline void expect_boundary_guarantees(ImageView image, Rect rect, const std::vector<Polygon>& polygons,
                                       const FilteredBoundary& options) {
    EXPECT_EQ(boundary_guarantee_failure(image, rect, polygons, options), "");
}

} // namespace depthcull::test
