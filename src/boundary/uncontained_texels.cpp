// The containment analyzer: count_uncontained_texels, the exact check of
// the boundary polygon guarantee (paper 2.1, grown by half a texel for
// bilinear filtering). Independent of the generator's own bookkeeping, so
// tests and `analyze --check` do not trust the code they check.
//
// A closed square lies in a closed polygon exactly when no polygon edge
// meets the square's open interior and the square's centre is strictly
// inside. Coordinates are scaled by a power of two to integers (exact for
// every dyadic coordinate, such as our half-texel grid); products use 128
// bits. A polygon whose coordinates are not dyadic (or absurdly large)
// cannot be checked exactly and is treated as containing nothing.
#include <algorithm>
#include <cmath>

#include "depthcull/analyze.h"

namespace depthcull {

namespace {

__extension__ typedef __int128 i128;

struct QPt {
    i128 x = 0, y = 0;
};

i128 orient(QPt a, QPt b, QPt c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }
int sign(i128 v) { return (v > 0) - (v < 0); }

constexpr int kScaleBits = 24;
constexpr double kMaxCoordinate = 1 << 30;

// Polygon coordinates times 2^kScaleBits, or false when not exact.
bool to_fixed(const Polygon& p, std::vector<QPt>& out) {
    out.clear();
    for (const Vec2& v : p) {
        if (!(std::fabs(v.x) < kMaxCoordinate && std::fabs(v.y) < kMaxCoordinate)) return false;
        double x = std::ldexp(v.x, kScaleBits), y = std::ldexp(v.y, kScaleBits);
        if (x != std::trunc(x) || y != std::trunc(y)) return false;
        out.push_back({i128(x), i128(y)});
    }
    return out.size() >= 3;
}

struct Square {
    i128 x0, y0, x1, y1;
};

// Closed segment pq meets the open square (separating axes: the square's
// axes and the segment's normal).
bool meets_open_square(QPt p, QPt q, const Square& s) {
    if (std::max(p.x, q.x) <= s.x0 || std::min(p.x, q.x) >= s.x1) return false;
    if (std::max(p.y, q.y) <= s.y0 || std::min(p.y, q.y) >= s.y1) return false;
    if (p.x == q.x && p.y == q.y) return true; // a point strictly inside the square
    int pos = 0, neg = 0;
    for (QPt c : {QPt{s.x0, s.y0}, QPt{s.x1, s.y0}, QPt{s.x1, s.y1}, QPt{s.x0, s.y1}}) {
        int o = sign(orient(p, q, c));
        pos += o > 0;
        neg += o < 0;
    }
    return pos && neg;
}

// (cx/2, cy/2) strictly inside; only called when no edge meets the open
// square around it, so it is never on the boundary.
bool centre_inside(const std::vector<QPt>& p, i128 cx, i128 cy) {
    bool inside = false;
    for (std::size_t i = 0, n = p.size(); i < n; ++i) {
        QPt a{2 * p[i].x, 2 * p[i].y}, b{2 * p[(i + 1) % n].x, 2 * p[(i + 1) % n].y};
        if ((a.y > cy) != (b.y > cy)) {
            i128 o = orient(a, b, QPt{cx, cy});
            if (b.y > a.y ? o > 0 : o < 0) inside = !inside;
        }
    }
    return inside;
}

bool square_inside(const std::vector<QPt>& p, const Square& s) {
    for (std::size_t i = 0, n = p.size(); i < n; ++i)
        if (meets_open_square(p[i], p[(i + 1) % n], s)) return false;
    return centre_inside(p, s.x0 + s.x1, s.y0 + s.y1);
}

} // namespace

std::int64_t count_uncontained_texels(ImageView image, Rect rect, const std::vector<Polygon>& polygons,
                                      Filter filter) {
    if (rect.empty() || !image.contains(rect)) return 0;
    struct Fixed {
        std::vector<QPt> points;
        i128 x0, y0, x1, y1; // bounds, to skip far squares quickly
    };
    std::vector<Fixed> fixed;
    for (const Polygon& polygon : polygons) {
        Fixed f;
        if (!to_fixed(polygon, f.points)) continue;
        f.x0 = f.x1 = f.points[0].x;
        f.y0 = f.y1 = f.points[0].y;
        for (QPt v : f.points) {
            f.x0 = std::min(f.x0, v.x), f.x1 = std::max(f.x1, v.x);
            f.y0 = std::min(f.y0, v.y), f.y1 = std::max(f.y1, v.y);
        }
        fixed.push_back(std::move(f));
    }
    const i128 one = i128(1) << kScaleBits, half = one / 2;
    const i128 grow = filter == Filter::linear ? half : 0;
    const i128 rx0 = rect.x * one, ry0 = rect.y * one, rx1 = (rect.x + rect.w) * one, ry1 = (rect.y + rect.h) * one;
    std::int64_t uncontained = 0;
    for (int y = rect.y; y < rect.y + rect.h; ++y)
        for (int x = rect.x; x < rect.x + rect.w; ++x) {
            if (is_transparent(image.alpha(x, y))) continue;
            Square s{std::max(x * one - grow, rx0), std::max(y * one - grow, ry0), std::min((x + 1) * one + grow, rx1),
                     std::min((y + 1) * one + grow, ry1)};
            bool inside = false;
            for (const Fixed& f : fixed) {
                if (s.x0 < f.x0 || s.x1 > f.x1 || s.y0 < f.y0 || s.y1 > f.y1) continue;
                if (square_inside(f.points, s)) {
                    inside = true;
                    break;
                }
            }
            uncontained += !inside;
        }
    return uncontained;
}

} // namespace depthcull
