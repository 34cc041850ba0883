// STUB (to be replaced by paper 2.2 and the fast algorithm).
#include "depthcull/analyze.h"

namespace depthcull {

std::vector<Polygon> generate_opaque_polygons(ImageView, Rect, const OpaqueOptions&) { return {}; }
std::int64_t count_opaque_violations(ImageView, Rect, const std::vector<Polygon>&, Filter) { return 0; }
std::int64_t count_covered_opaque_texels(ImageView, Rect, const std::vector<Polygon>&) { return 0; }

} // namespace depthcull
