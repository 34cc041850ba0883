// The analyzers beside the opaque search: count_opaque_violations checks the
// guarantee of analyze.h exactly, count_covered_opaque_texels measures what
// the polygons achieve (the best case covers every opaque texel).
//
// Polygons are converted to integers in units of 1/256 texel, which holds
// every vertex the stages emit (halves) exactly; all predicates below are
// then exact integer arithmetic. Coordinates off that grid are rounded to it.
#include <algorithm>
#include <cmath>

#include "opaque/opaque_internal.h"

namespace depthcull {

namespace {

using opaque_detail::HalfPoint;
using opaque_detail::HalfPolygon;
using opaque_detail::i64;

constexpr i64 kScale = 256;

HalfPolygon to_fixed(const Polygon& p) {
    HalfPolygon out;
    for (const auto& v : p) {
        HalfPoint q{std::llround(v.x * kScale), std::llround(v.y * kScale)};
        if (out.empty() || !(out.back() == q)) out.push_back(q);
    }
    while (out.size() > 1 && out.front() == out.back()) out.pop_back();
    // Checkers accept either orientation; the searches emit clockwise.
    i64 twice = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const HalfPoint& a = out[i];
        const HalfPoint& b = out[(i + 1) % out.size()];
        twice += a.x * b.y - a.y * b.x;
    }
    if (twice < 0) std::reverse(out.begin(), out.end());
    return out;
}

i64 orient(HalfPoint a, HalfPoint b, HalfPoint c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

struct Square {
    HalfPoint corner[4]; // clockwise
    i64 x0, y0, x1, y1;
};

Square texel_square(int x, int y) {
    i64 x0 = x * kScale, y0 = y * kScale, x1 = x0 + kScale, y1 = y0 + kScale;
    return {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, x0, y0, x1, y1};
}

// Separating-axis test on the edges of both convex shapes. `strict`: the
// closed shapes are disjoint; otherwise: the interiors are disjoint.
bool separated(const HalfPolygon& p, const Square& s, bool strict) {
    i64 x0 = p[0].x, x1 = p[0].x, y0 = p[0].y, y1 = p[0].y;
    for (const auto& v : p) {
        x0 = std::min(x0, v.x), x1 = std::max(x1, v.x);
        y0 = std::min(y0, v.y), y1 = std::max(y1, v.y);
    }
    auto apart = [&](i64 a_max, i64 b_min) { return strict ? a_max < b_min : a_max <= b_min; };
    if (apart(x1, s.x0) || apart(s.x1, x0) || apart(y1, s.y0) || apart(s.y1, y0)) return true;
    for (std::size_t i = 0, n = p.size(); i < n && n > 1; ++i) {
        HalfPoint a = p[i], b = p[(i + 1) % n];
        bool all_out = true;
        for (const auto& c : s.corner) {
            i64 o = orient(a, b, c);
            all_out = all_out && (strict ? o < 0 : o <= 0);
        }
        if (all_out) return true;
    }
    return false;
}

bool edge_along_side(const HalfPolygon& p, const Square& s) {
    for (std::size_t i = 0, n = p.size(); i < n; ++i) {
        HalfPoint a = p[i], b = p[(i + 1) % n];
        if (a.y == b.y && (a.y == s.y0 || a.y == s.y1) &&
            std::min(std::max(a.x, b.x), s.x1) > std::max(std::min(a.x, b.x), s.x0))
            return true;
        if (a.x == b.x && (a.x == s.x0 || a.x == s.x1) &&
            std::min(std::max(a.y, b.y), s.y1) > std::max(std::min(a.y, b.y), s.y0))
            return true;
    }
    return false;
}

// Squared distance from p to segment ab is < kScale^2 / 4 (half a texel).
bool closer_than_half(HalfPoint p, HalfPoint a, HalfPoint b) {
    __extension__ typedef __int128 i128; // products of squared distances need 94 bits
    const i128 limit = i128(kScale) * kScale / 4;
    i64 abx = b.x - a.x, aby = b.y - a.y, apx = p.x - a.x, apy = p.y - a.y;
    i128 t = i128(apx) * abx + i128(apy) * aby;
    i128 len2 = i128(abx) * abx + i128(aby) * aby;
    if (t <= 0 || len2 == 0) return i128(apx) * apx + i128(apy) * apy < limit;
    if (t >= len2) {
        i64 bpx = p.x - b.x, bpy = p.y - b.y;
        return i128(bpx) * bpx + i128(bpy) * bpy < limit;
    }
    i128 c = i128(abx) * apy - i128(aby) * apx;
    return c * c < limit * len2;
}

bool violates(const HalfPolygon& p, const Square& s, Filter filter) {
    if (filter == Filter::nearest) {
        if (p.size() >= 3 && !separated(p, s, false)) return true;
        return edge_along_side(p, s);
    }
    // Linear: the polygon must keep a distance >= 0.5 from the square (0.5
    // exactly is allowed: the bilinear footprint of a texel reaches half a
    // texel beyond its square, and at exactly 0.5 its weight is zero).
    if (!separated(p, s, true)) return true;
    for (std::size_t i = 0, n = p.size(); i < n; ++i) {
        HalfPoint a = p[i], b = p[(i + 1) % n];
        for (int k = 0; k < 4; ++k) {
            if (closer_than_half(s.corner[k], a, b)) return true;
            if (closer_than_half(a, s.corner[k], s.corner[(k + 1) % 4])) return true;
        }
    }
    return false;
}

bool opaque_in_rect(ImageView image, Rect rect, int x, int y) {
    return x >= rect.x && y >= rect.y && x < rect.x + rect.w && y < rect.y + rect.h && is_opaque(image.alpha(x, y));
}

} // namespace

std::int64_t count_opaque_violations(ImageView image, Rect rect, const std::vector<Polygon>& polygons, Filter filter) {
    std::vector<i64> violated; // texel keys, deduplicated at the end
    for (const auto& polygon : polygons) {
        HalfPolygon p = to_fixed(polygon);
        if (p.empty()) continue;
        i64 x0 = p[0].x, x1 = p[0].x, y0 = p[0].y, y1 = p[0].y;
        for (const auto& v : p) {
            x0 = std::min(x0, v.x), x1 = std::max(x1, v.x);
            y0 = std::min(y0, v.y), y1 = std::max(y1, v.y);
        }
        // Every texel within half a texel of the polygon's box.
        const i64 tx0 = floor_div(x0, kScale) - 1, tx1 = ceil_div(x1, kScale);
        const i64 ty0 = floor_div(y0, kScale) - 1, ty1 = ceil_div(y1, kScale);
        for (i64 y = ty0; y <= ty1; ++y)
            for (i64 x = tx0; x <= tx1; ++x) {
                if (opaque_in_rect(image, rect, int(x), int(y))) continue;
                if (violates(p, texel_square(int(x), int(y)), filter)) violated.push_back((y << 32) ^ (x & 0xffffffff));
            }
    }
    std::sort(violated.begin(), violated.end());
    return std::unique(violated.begin(), violated.end()) - violated.begin();
}

std::int64_t count_centre_covered_opaque_texels(ImageView image, Rect rect, const std::vector<Polygon>& polygons) {
    if (rect.empty() || !image.contains(rect)) return 0;
    // Strictly inside a convex polygon: every edge has the centre on its
    // inner side (exact: 1/256 texel integers, either orientation; a centre
    // on an edge is not drawn once the opaque pass pulls polygons in). Opaque
    // texels only (the guarantee makes them all opaque; a broken polygon
    // must not score).
    std::vector<std::uint8_t> hit(std::size_t(rect.w) * std::size_t(rect.h), 0);
    for (const auto& polygon : polygons) {
        const HalfPolygon p = to_fixed(polygon);
        if (p.size() < 3) continue;
        i64 twice = 0, x0 = p[0].x, x1 = p[0].x, y0 = p[0].y, y1 = p[0].y;
        for (std::size_t i = 0; i < p.size(); ++i) {
            const HalfPoint& a = p[i];
            const HalfPoint& b = p[(i + 1) % p.size()];
            twice += a.x * b.y - b.x * a.y;
            x0 = std::min(x0, a.x), x1 = std::max(x1, a.x), y0 = std::min(y0, a.y), y1 = std::max(y1, a.y);
        }
        if (twice == 0) continue;
        const i64 sign = twice > 0 ? 1 : -1;
        const i64 tx0 = std::max<i64>(rect.x, floor_div(x0, kScale) - 1), tx1 = std::min<i64>(rect.x + rect.w - 1, ceil_div(x1, kScale));
        const i64 ty0 = std::max<i64>(rect.y, floor_div(y0, kScale) - 1), ty1 = std::min<i64>(rect.y + rect.h - 1, ceil_div(y1, kScale));
        for (i64 y = ty0; y <= ty1; ++y)
            for (i64 x = tx0; x <= tx1; ++x) {
                const i64 cx = kScale * x + kScale / 2, cy = kScale * y + kScale / 2;
                bool in = true;
                for (std::size_t i = 0; i < p.size() && in; ++i) {
                    const HalfPoint& a = p[i];
                    const HalfPoint& b = p[(i + 1) % p.size()];
                    in = sign * ((b.x - a.x) * (cy - a.y) - (b.y - a.y) * (cx - a.x)) > 0;
                }
                if (in) hit[std::size_t(y - rect.y) * std::size_t(rect.w) + std::size_t(x - rect.x)] = 1;
            }
    }
    std::int64_t n = 0;
    for (int y = rect.y; y < rect.y + rect.h; ++y)
        for (int x = rect.x; x < rect.x + rect.w; ++x)
            n += hit[std::size_t(y - rect.y) * std::size_t(rect.w) + std::size_t(x - rect.x)] && is_opaque(image.alpha(x, y));
    return n;
}

std::int64_t count_covered_opaque_texels(ImageView image, Rect rect, const std::vector<Polygon>& polygons) {
    if (rect.empty() || !image.contains(rect)) return 0;
    std::vector<HalfPolygon> fixed;
    for (const auto& polygon : polygons) {
        HalfPolygon p = to_fixed(polygon);
        if (p.size() >= 3) fixed.push_back(std::move(p));
    }
    std::int64_t n = 0;
    std::vector<std::pair<i64, i64>> spans;
    for (int y = rect.y; y < rect.y + rect.h; ++y) {
        spans.clear();
        for (const auto& p : fixed) {
            i64 lo, hi;
            opaque_detail::covered_columns(p, y, lo, hi, kScale);
            lo = std::max<i64>(lo, rect.x), hi = std::min<i64>(hi, rect.x + rect.w);
            if (lo < hi) spans.push_back({lo, hi});
        }
        std::sort(spans.begin(), spans.end());
        i64 done = rect.x; // texels left of this are counted
        for (auto [lo, hi] : spans) {
            for (i64 x = std::max(lo, done); x < hi; ++x) n += is_opaque(image.alpha(int(x), y));
            done = std::max(done, hi);
        }
    }
    return n;
}

} // namespace depthcull
