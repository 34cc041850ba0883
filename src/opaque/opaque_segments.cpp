// Paper 2.2.1: opaque segments and their graph, plus the exact grid
// arithmetic (safe texels, span counts, covered columns) both opaque searches
// share.
#include <algorithm>
#include <limits>

#include "opaque/opaque_internal.h"

namespace depthcull::opaque_detail {

Polygon to_polygon(const HalfPolygon& p, Rect rect) {
    Polygon out;
    out.reserve(p.size());
    // Halves are exact in a double, so the public vertices are exact too.
    for (const auto& v : p) out.push_back({rect.x + double(v.x) / 2, rect.y + double(v.y) / 2});
    return out;
}

Polygon to_polygon(const HalfPolygon& p, Rect rect, i64 scale) {
    Polygon out;
    out.reserve(p.size());
    for (const auto& v : p) out.push_back({rect.x + double(v.x) / double(scale), rect.y + double(v.y) / double(scale)});
    return out;
}

std::vector<Segment> find_opaque_segments(const Mask& mask, int min_length) {
    std::vector<Segment> segments;
    std::size_t prev_begin = 0, prev_end = 0; // segments of the previous row
    for (int y = 0; y < mask.height; ++y) {
        std::size_t row_begin = segments.size();
        for (int x = 0; x < mask.width;) {
            while (x < mask.width && !mask.at(x, y)) ++x;
            if (x >= mask.width) break;
            int x0 = x;
            while (x < mask.width && mask.at(x, y)) ++x;
            if (x - x0 < min_length) continue; // paper: ignore runs shorter than 3
            segments.push_back({x0, x - 1, y, {}});
        }
        // Paper 2.2.1 links each segment to the overlapping ones above it; the
        // rows are sorted by x, so a merge finds them in O(N) instead of the
        // pseudocode's scan over every segment.
        std::size_t j = prev_begin;
        for (std::size_t i = row_begin; i < segments.size(); ++i) {
            while (j < prev_end && segments[j].x1 < segments[i].x0) ++j;
            for (std::size_t k = j; k < prev_end && segments[k].x0 <= segments[i].x1; ++k)
                segments[k].down.push_back(int(i));
        }
        prev_begin = row_begin;
        prev_end = segments.size();
    }
    return segments;
}

Mask safe_mask(ImageView image, Rect rect, Filter filter) {
    Mask opaque = opaque_mask(image, rect);
    if (filter == Filter::nearest) return opaque;
    Mask safe = opaque;
    for (int y = 0; y < opaque.height; ++y)
        for (int x = 0; x < opaque.width; ++x) {
            if (!opaque.at(x, y)) continue;
            bool ok = true;
            for (int dy = -1; dy <= 1 && ok; ++dy)
                for (int dx = -1; dx <= 1 && ok; ++dx) {
                    int nx = x + dx, ny = y + dy;
                    ok = nx >= 0 && ny >= 0 && nx < opaque.width && ny < opaque.height && opaque.at(nx, ny);
                }
            safe.bits[std::size_t(y) * safe.width + x] = ok ? 1 : 0;
        }
    return safe;
}

RowSums::RowSums(const Mask& mask, bool count_set) : width_(mask.width), height_(mask.height) {
    sums_.assign(std::size_t(width_ + 1) * height_, 0);
    for (int y = 0; y < height_; ++y) {
        std::int32_t* row = &sums_[std::size_t(y) * (width_ + 1)];
        for (int x = 0; x < width_; ++x) row[x + 1] = row[x] + ((mask.at(x, y) != 0) == count_set ? 1 : 0);
    }
}

i64 RowSums::span_clipped(int y, int x0, int x1, i64 outside) const {
    if (y < 0 || y >= height_) return outside * (x1 - x0);
    i64 n = 0;
    if (x0 < 0) n += outside * (std::min(x1, 0) - x0);
    if (x1 > width_) n += outside * (x1 - std::max(x0, width_));
    int a = std::clamp(x0, 0, width_), b = std::clamp(x1, 0, width_);
    if (a < b) {
        const std::int32_t* row = &sums_[std::size_t(y) * (width_ + 1)];
        n += i64(row[b]) - row[a];
    }
    return n;
}

namespace {

// Narrows [lo, hi) to the columns i whose sample points at height y (units
// of 1/scale texel) lie inside the convex clockwise polygon p: the point
// x = scale i + at_left must not be left of any left boundary edge, and
// x = scale i + at_right not right of any right boundary edge. Each
// clockwise edge a->b keeps the points with cross(b - a, q - a) >= 0; for a
// fixed y that bounds x from one side. False when the row is empty.
bool narrow_columns(const HalfPolygon& p, i64 y, i64 at_left, i64 at_right, i64 scale, i64& lo, i64& hi) {
    for (std::size_t k = 0, n = p.size(); k < n; ++k) {
        const HalfPoint a = p[k], b = p[(k + 1) % n];
        const i64 dx = b.x - a.x, dy = b.y - a.y;
        if (dy == 0) {
            if (dx * (y - a.y) < 0) return false;
        } else if (dy > 0) { // right boundary: scale i + at_right <= a.x + dx (y - a.y) / dy
            hi = std::min(hi, floor_div(a.x * dy + dx * (y - a.y) - at_right * dy, scale * dy) + 1);
        } else { // left boundary: scale i + at_left >= a.x - dx (y - a.y) / e
            const i64 e = -dy;
            lo = std::max(lo, ceil_div(a.x * e - dx * (y - a.y) - at_left * e, scale * e));
        }
    }
    return true;
}

} // namespace

void covered_columns(const HalfPolygon& p, int row, i64& lo, i64& hi, i64 scale) {
    // A closed texel square is inside a convex polygon iff its four corners
    // are: its left corners x = scale i and right corners x = scale (i + 1),
    // at both corner rows.
    lo = std::numeric_limits<i64>::min() / 4;
    hi = std::numeric_limits<i64>::max() / 4;
    for (i64 y : {scale * i64(row), scale * (i64(row) + 1)})
        if (!narrow_columns(p, y, 0, scale, scale, lo, hi)) {
            hi = lo;
            return;
        }
}

i64 centre_covered_texels(const std::vector<HalfPolygon>& polygons, i64 scale) {
    // Row r's centres lie at y = scale r + scale / 2; a convex polygon's
    // interior meets that line only strictly between its lowest and highest
    // y, where it spans the open range between its crossings num / den, and
    // texel x has its centre in it iff scale x + scale / 2 lies strictly
    // inside: exact integers.
    const i64 half = scale / 2;
    i64 y0 = std::numeric_limits<i64>::max(), y1 = std::numeric_limits<i64>::min();
    for (const HalfPolygon& p : polygons)
        for (const HalfPoint& v : p) y0 = std::min(y0, v.y), y1 = std::max(y1, v.y);
    if (y0 > y1) return 0;
    i64 count = 0;
    std::vector<std::pair<i64, i64>> spans;
    for (i64 row = floor_div(y0, scale); row <= ceil_div(y1, scale); ++row) {
        const i64 y = scale * row + half;
        spans.clear();
        for (const HalfPolygon& p : polygons) {
            i64 lo = std::numeric_limits<i64>::max(), hi = std::numeric_limits<i64>::min();
            i64 top = std::numeric_limits<i64>::max(), bottom = std::numeric_limits<i64>::min();
            for (const HalfPoint& v : p) top = std::min(top, v.y), bottom = std::max(bottom, v.y);
            if (y <= top || y >= bottom) continue;
            auto cross = [&](i64 num, i64 den) {
                lo = std::min(lo, floor_div(num - den * half, scale * den) + 1);
                hi = std::max(hi, ceil_div(num - den * half, scale * den) - 1);
            };
            for (std::size_t k = 0, n = p.size(); k < n; ++k) {
                const HalfPoint a = p[k], b = p[(k + 1) % n];
                if (a.y == y) cross(a.x, 1);
                if (y <= std::min(a.y, b.y) || y >= std::max(a.y, b.y)) continue;
                i64 num = a.x * (b.y - a.y) + (b.x - a.x) * (y - a.y), den = b.y - a.y;
                if (den < 0) num = -num, den = -den;
                cross(num, den);
            }
            if (lo <= hi) spans.push_back({lo, hi + 1});
        }
        std::sort(spans.begin(), spans.end());
        i64 done = std::numeric_limits<i64>::min();
        for (auto [lo, hi] : spans) {
            const i64 from = std::max(lo, done);
            if (hi > from) count += hi - from;
            done = std::max(done, hi);
        }
    }
    return count;
}

void band_columns(const HalfPolygon& p, i64 y0, i64 y1, i64 margin, i64& lo, i64& hi) {
    // The polygon's open interior within the open band spans the open x
    // range between the extremes of the polygon cut to the closed band
    // (convex), widened by `margin`; a texel's open square meets it iff
    // their x ranges overlap.
    lo = std::numeric_limits<i64>::max(), hi = std::numeric_limits<i64>::min();
    for (std::size_t k = 0, n = p.size(); k < n; ++k) {
        const HalfPoint a = p[k], b = p[(k + 1) % n];
        if (a.y >= y0 && a.y <= y1)
            lo = std::min(lo, floor_div(a.x - margin, 2)), hi = std::max(hi, ceil_div(a.x + margin, 2));
        if (a.y == b.y) continue;
        for (i64 y : {y0, y1}) {
            if (y <= std::min(a.y, b.y) || y >= std::max(a.y, b.y)) continue;
            i64 num = a.x * (b.y - a.y) + (b.x - a.x) * (y - a.y), den = b.y - a.y;
            if (den < 0) num = -num, den = -den;
            lo = std::min(lo, floor_div(num - margin * den, 2 * den)), hi = std::max(hi, ceil_div(num + margin * den, 2 * den));
        }
    }
}

void touched_columns(const HalfPolygon& p, int row, i64& lo, i64& hi, i64 margin) {
    // The polygon grown by a square of half-side `margin` reaches the row's
    // band where the polygon reaches the band widened by `margin`, `margin`
    // further out on each side.
    i64 ymin = p[0].y, ymax = p[0].y;
    for (const HalfPoint& v : p) ymin = std::min(ymin, v.y), ymax = std::max(ymax, v.y);
    const i64 y0 = std::max(2 * i64(row) - margin, ymin), y1 = std::min(2 * i64(row) + 2 + margin, ymax);
    if (y1 <= y0) {
        lo = hi = 0;
        return;
    }
    band_columns(p, y0, y1, margin, lo, hi);
}

} // namespace depthcull::opaque_detail
