// Paper 2.3.2: depth values. The paper's AssignDepthValues walks the
// elements in painter's order giving each one more than every element it
// overlaps behind it: the longest path to the far plane in the element
// graph. We do the same on the graph's adjacency lists (linear in edges);
// steps of 2 in z leave the paper's "k + epsilon" for opaque polygons.
#include <algorithm>
#include <cmath>

#include "depthcull/scene.h"

namespace depthcull {

std::vector<std::int64_t> assign_depth_levels(const ElementGraph& graph) {
    std::vector<std::int64_t> level(graph.size(), 0);
    // Edges point from i to j < i, so one pass in index order sees every
    // element's back neighbours finished.
    for (std::size_t i = 0; i < graph.size(); ++i)
        for (const std::uint32_t* b = graph.behind_begin(i); b != graph.behind_end(i); ++b)
            level[i] = std::max(level[i], level[*b] + 1);
    return level;
}

std::int64_t depth_denominator(std::int64_t levels) {
    // Powers of two keep (2k+1)/D and (2k+2)/D exact in a float; the
    // smallest D that fits spreads the values as far apart as possible,
    // so small scenes also work with 16-bit depth buffers.
    std::int64_t d = 256;
    while (d < 2 * levels + 2) d *= 2;
    return d;
}

std::int64_t depth_levels_of_draws(const std::vector<Draw>& draws, std::int64_t denominator) {
    if (denominator < 2) return 0;
    // Level k draws at (2k+1)/D and (2k+2)/D: k + 1 = ceil(z * D / 2).
    // Values outside [0, 1] (or NaN) name no level of the mapping; the
    // readers refuse them, and here they count as the top.
    double top = 0;
    for (const Draw& d : draws)
        for (std::size_t k = 2; k < d.vertices.size(); k += kVertexFloats) {
            const double z = d.vertices[k];
            if (!(z <= 1)) return denominator / 2;
            top = std::max(top, z);
        }
    return std::int64_t(std::ceil(top * double(denominator) / 2));
}

} // namespace depthcull
