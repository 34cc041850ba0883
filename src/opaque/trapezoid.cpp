// Exact validity and coverage of the quads both opaque searches produce
// (paper 2.2.2 "quadrilaterals with horizontal top and bottom edges"), in
// O(rows) with row prefix sums instead of the paper's O(area) scans.
#include <algorithm>

#include "opaque/opaque_internal.h"

namespace depthcull::opaque_detail {

HalfPolygon Trapezoid::polygon() const {
    HalfPolygon p;
    p.push_back({xlt, yt});
    if (xrt != xlt) p.push_back({xrt, yt});
    p.push_back({xrb, yb});
    if (xlb != xrb) p.push_back({xlb, yb});
    return p;
}

namespace {

Mask transposed(const Mask& m) {
    Mask t;
    t.width = m.height;
    t.height = m.width;
    t.bits.resize(m.bits.size());
    // In tiles, so that large images do not miss the cache on every write.
    constexpr int kTile = 64;
    for (int y0 = 0; y0 < m.height; y0 += kTile)
        for (int x0 = 0; x0 < m.width; x0 += kTile)
            for (int y = y0; y < std::min(y0 + kTile, m.height); ++y)
                for (int x = x0; x < std::min(x0 + kTile, m.width); ++x)
                    t.bits[std::size_t(x) * m.height + y] = m.bits[std::size_t(y) * m.width + x];
    return t;
}

} // namespace

SafeGrid::SafeGrid(const Mask& safe)
    : width(safe.width), height(safe.height), unsafe(safe, /*count_set=*/false),
      unsafe_columns(transposed(safe), /*count_set=*/false), safe_mask(safe) {}

namespace {

// x of a side at height y, as a numerator over (yb - yt).
i64 side_numerator(i64 x_top, i64 x_bottom, const Trapezoid& t, i64 y) {
    return x_top * (t.yb - t.yt) + (x_bottom - x_top) * (y - t.yt);
}

bool column_safe(const SafeGrid& grid, i64 column, i64 y0, i64 y1) {
    return grid.unsafe_columns.span(int(column), int(y0), int(y1), 1) == 0;
}

} // namespace

bool trapezoid_edges_valid(const Trapezoid& t, const SafeGrid& grid) {
    if (t.yb <= t.yt || t.xrt < t.xlt || t.xrb < t.xlb || (t.xrt == t.xlt && t.xrb == t.xlb)) return false;
    const i64 row0 = floor_div(t.yt, 2), row1 = ceil_div(t.yb, 2);
    if (row0 < 0 || row1 > grid.height || std::min(t.xlt, t.xlb) < 0 || std::max(t.xrt, t.xrb) > 2 * i64(grid.width))
        return false;
    // Edges on grid lines must not run along an unsafe texel's side; O(1)
    // each, so they go first.
    if (t.yt % 2 == 0 && t.xrt > t.xlt &&
        grid.unsafe.span(int(t.yt / 2 - 1), int(floor_div(t.xlt, 2)), int(ceil_div(t.xrt, 2)), 1) != 0)
        return false;
    if (t.yb % 2 == 0 && t.xrb > t.xlb &&
        grid.unsafe.span(int(t.yb / 2), int(floor_div(t.xlb, 2)), int(ceil_div(t.xrb, 2)), 1) != 0)
        return false;
    if (t.xlt == t.xlb && t.xlt % 2 == 0 && !column_safe(grid, t.xlt / 2 - 1, row0, row1)) return false;
    if (t.xrt == t.xrb && t.xrt % 2 == 0 && !column_safe(grid, t.xrt / 2, row0, row1)) return false;
    return true;
}

bool trapezoid_valid(const Trapezoid& t, const SafeGrid& grid, i64& work) {
    if (!trapezoid_edges_valid(t, grid)) return false;
    const i64 den2 = 2 * (t.yb - t.yt);
    const i64 row0 = floor_div(t.yt, 2), row1 = ceil_div(t.yb, 2);
    work += row1 - row0;
    // Interior: in row j the open strip meets the quad between the smallest
    // left-side x and the largest right-side x over the strip's ends (the
    // sides are straight); every texel whose open square meets that range
    // must be safe.
    auto row_ok = [&](i64 j, i64 lo, i64 hi) {
        return lo >= 0 && hi <= grid.width && grid.unsafe.span(int(j), int(lo), int(hi), 1) == 0;
    };
    // Rows cut by the top or bottom edge, in general.
    auto clipped_row_ok = [&](i64 j) {
        i64 s0 = std::max(2 * j, t.yt), s1 = std::min(2 * j + 2, t.yb);
        i64 lo = std::min(floor_div(side_numerator(t.xlt, t.xlb, t, s0), den2),
                          floor_div(side_numerator(t.xlt, t.xlb, t, s1), den2));
        i64 hi = std::max(ceil_div(side_numerator(t.xrt, t.xrb, t, s0), den2),
                          ceil_div(side_numerator(t.xrt, t.xrb, t, s1), den2));
        return row_ok(j, lo, hi);
    };
    // Whole rows: the leftmost point of the left side within a row is at its
    // top end when the side leans right going down, and so on; step those
    // ends row by row.
    const i64 full0 = ceil_div(t.yt, 2), full1 = floor_div(t.yb, 2);
    for (i64 j = row0; j < std::min(full0, row1); ++j)
        if (!clipped_row_ok(j)) return false;
    if (full0 < full1) {
        const i64 dl = t.xlb - t.xlt, dr = t.xrb - t.xrt;
        const i64 l_end = dl >= 0 ? 0 : 2, r_end = dr >= 0 ? 2 : 0;
        FloorStepper lo(2 * dl, side_numerator(t.xlt, t.xlb, t, 2 * full0 + l_end), den2);
        FloorStepper hi(2 * dr, side_numerator(t.xrt, t.xrb, t, 2 * full0 + r_end) + den2 - 1, den2);
        for (i64 j = full0; j < full1; ++j, lo.next(), hi.next())
            if (!row_ok(j, lo.value(), hi.value())) return false;
    }
    for (i64 j = std::max(full1, full0); j < row1; ++j)
        if (!clipped_row_ok(j)) return false;
    return true;
}

i64 floor_sum(i64 n, i64 m, i64 a, i64 b) {
    i64 ans = 0;
    // Move a and b into [0, m), then the Euclid-like reduction.
    if (a < 0 || a >= m) {
        i64 q = floor_div(a, m);
        ans += n * (n - 1) / 2 * q;
        a -= q * m;
    }
    if (b < 0 || b >= m) {
        i64 q = floor_div(b, m);
        ans += n * q;
        b -= q * m;
    }
    while (true) {
        if (a >= m) {
            ans += n * (n - 1) / 2 * (a / m);
            a %= m;
        }
        if (b >= m) {
            ans += n * (b / m);
            b %= m;
        }
        i64 y_max = a * n + b;
        if (y_max < m) break;
        n = y_max / m;
        b = y_max % m;
        std::swap(m, a);
    }
    return ans;
}

i64 paper_span_total(const PaperQuad& q) {
    const i64 dy = q.y1 - q.y0;
    // sum_k round(d k / dy), half away from zero, k = 0 .. dy - 1.
    auto rounded = [&](i64 d) {
        return d >= 0 ? floor_sum(dy, 2 * dy, 2 * d, dy) : -floor_sum(dy, 2 * dy, -2 * d, dy);
    };
    return dy * (q.x1 - q.x0) + rounded(q.x2 - q.x1) - rounded(q.x3 - q.x0);
}

} // namespace depthcull::opaque_detail
