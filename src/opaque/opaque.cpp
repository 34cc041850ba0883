// Paper 2.2: opaque polygon generation, the public entry point. The two
// searches live in paper_quad_search.cpp (the paper, the reference) and
// fast_search.cpp (ours, the default); both run against the same mask of
// texels an opaque polygon may touch (opaque_segments.cpp: safe_mask).
#include <algorithm>

#include "opaque/opaque_internal.h"

namespace depthcull {

std::vector<Polygon> generate_opaque_polygons(ImageView image, Rect rect, const OpaqueOptions& options, Filter filter,
                                              OpaqueSearchStats* stats) {
    using namespace opaque_detail;
    std::vector<Polygon> result;
    if (stats) *stats = {};
    if (rect.empty() || !image.contains(rect) || options.max_polygons <= 0) return result;
    Mask safe = safe_mask(image, rect, filter);
    // No texel may be touched: no polygon, and none of the searches' grids
    // (about 20-30 bytes per texel) for a transparent or translucent image.
    if (std::all_of(safe.bits.begin(), safe.bits.end(), [](std::uint8_t b) { return b == 0; })) return result;
    SearchCounters counters;
    std::vector<HalfPolygon> polygons;
    switch (options.method) {
    case OpaqueMethod::paper: polygons = paper_opaque_polygons(safe, options, counters); break;
    case OpaqueMethod::grow: polygons = grow_opaque_polygons(SafeGrid(safe), options, counters).polygons; break;
    case OpaqueMethod::fast: polygons = fast_opaque_polygons(safe, options, counters); break;
    case OpaqueMethod::cover: polygons = cover_opaque_polygons(safe, options, counters); break;
    }
    const i64 scale = options.method == OpaqueMethod::cover ? kCoverScale : 2;
    for (const auto& p : polygons) result.push_back(to_polygon(p, rect, scale));
    if (stats) *stats = {counters.candidates, counters.work, counters.budget_exhausted};
    return result;
}

std::vector<Polygon> generate_opaque_polygons(ImageView image, Rect rect, const OpaqueOptions& options, Filter filter) {
    return generate_opaque_polygons(image, rect, options, filter, nullptr);
}

} // namespace depthcull
