// texel_map: the one map from screen to texels every way of drawing an
// element shares (depthcull/scene.h says why it is solved from the float
// corners). Out of line: a public header carries its declaration only.
#include <array>
#include <cmath>

#include "depthcull/scene.h"

namespace depthcull {

TexelMap texel_map(const Element& e) {
    TexelMap t;
    t.rect = e.rect;
    auto corner = [&](double u, double v) {
        const auto& m = e.transform;
        return std::array<double, 2>{double(float(m[0] * u + m[2] * v + m[4])), double(float(m[1] * u + m[3] * v + m[5]))};
    };
    const auto o = corner(0, 0), a = corner(e.rect.w, 0), b = corner(0, e.rect.h);
    const double ax = a[0] - o[0], ay = a[1] - o[1], bx = b[0] - o[0], by = b[1] - o[1];
    const double det = ax * by - ay * bx;
    if (!(det != 0) || !std::isfinite(det)) {
        t.u0 = e.rect.x, t.v0 = e.rect.y;
        t.ux = t.uy = t.vx = t.vy = 0;
        return t;
    }
    // Screen offset (x, y) - o = u' * a + v' * b with u' = (u - x0) / w, v' = (v - y0) / h.
    t.ux = by / det * e.rect.w;
    t.uy = -bx / det * e.rect.w;
    t.vx = -ay / det * e.rect.h;
    t.vy = ax / det * e.rect.h;
    t.u0 = double(e.rect.x) - (t.ux * o[0] + t.uy * o[1]);
    t.v0 = double(e.rect.y) - (t.vx * o[0] + t.vy * o[1]);
    return t;
}

} // namespace depthcull
