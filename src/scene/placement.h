// Internal to the library (src/scene, and src/cost, which must predict
// what reconstruction does): how GL will place an element's vertices.
// Kept apart from scene/internal.h so the cost model sees only these.
#pragma once

#include <array>
#include <vector>

#include "depthcull/scene.h"

namespace depthcull::detail {

// True when GL rasterizes the element's polygons without snapping error
// (power-of-two scales, quarter turns or flips, moved by a multiple of
// 1/256 pixel): such elements need no texel skirt (texel_margin.cpp).
bool snaps_exactly(const std::array<double, 6>& transform);

// True when the element's rect lands on whole screen pixels along the
// axes: a wholly opaque rect can then be its own opaque polygon
// (shapes.cpp).
bool pixel_aligned(const Scene& scene, const Element& e);

// An opaque polygon of the element's analysis as its element may draw it
// (issue 25): with nearest filtering and the element pixel-aligned, each
// axis-parallel edge the analysis kept half a texel inside a side of the
// rect, between edges at right angles to it, moved out onto that side;
// else the polygon unchanged. See shapes.cpp for why that is safe.
Polygon opaque_to_rect_sides(const Scene& scene, const Element& e, const Polygon& p);

// Per edge of `texel` (a convex polygon of element e, texel space): 0 for
// an edge on a side of e's rect when e is pixel-aligned under nearest
// filtering (no pixel centre lies near it: GL has nothing to snap, and an
// opaque polygon there meets the rect's own edge exactly), else `margin`
// (texel_margin.cpp).
std::vector<double> side_margins(const Scene& scene, const Element& e, const Polygon& texel, double margin);

} // namespace depthcull::detail
