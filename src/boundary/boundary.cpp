// STUB (to be replaced by the paper 2.1 implementation): the bounding box.
#include "depthcull/analyze.h"

namespace depthcull {

std::vector<Polygon> generate_boundary_polygons(ImageView image, Rect rect, const BoundaryOptions& options) {
    Mask m = nontransparent_mask(image, rect);
    int x0 = m.width, y0 = m.height, x1 = -1, y1 = -1;
    for (int y = 0; y < m.height; ++y)
        for (int x = 0; x < m.width; ++x)
            if (m.at(x, y)) {
                x0 = std::min(x0, x); x1 = std::max(x1, x);
                y0 = std::min(y0, y); y1 = std::max(y1, y);
            }
    if (x1 < 0) return {};
    double g = options.filter == Filter::linear ? 0.5 : 0.0;
    double X0 = rect.x + x0 - g, Y0 = rect.y + y0 - g, X1 = rect.x + x1 + 1 + g, Y1 = rect.y + y1 + 1 + g;
    return {Polygon{{X0, Y0}, {X1, Y0}, {X1, Y1}, {X0, Y1}}};
}

std::int64_t count_uncontained_texels(ImageView, Rect, const std::vector<Polygon>&, Filter) { return 0; }

} // namespace depthcull
