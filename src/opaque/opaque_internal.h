// Internals shared by the opaque-polygon stage (paper 2.2): opaque segments,
// the exact grid arithmetic both searches use, and the two searches.
//
// Coordinates inside the stage are relative to the analyzed rect and kept
// in *half texels* (integers, value 2 == one texel), because every vertex we
// emit lies on the half grid (the paper pushes quads in by 0.5). All
// predicates are then exact integer arithmetic.
#pragma once

#include <cstdint>
#include <vector>

#include "depthcull/analyze.h"

namespace depthcull::opaque_detail {

using i64 = std::int64_t;


// floor((a j + b) / m) for j = 0, 1, 2, ... without a division per step
// (m > 0): the sides of a quad, row by row.
class FloorStepper {
public:
    FloorStepper(i64 a, i64 b, i64 m) : m_(m) {
        q_ = floor_div(b, m), r_ = b - q_ * m;
        aq_ = floor_div(a, m), ar_ = a - aq_ * m;
    }
    i64 value() const { return q_; }
    void next() {
        q_ += aq_;
        r_ += ar_;
        if (r_ >= m_) r_ -= m_, ++q_;
    }

private:
    i64 m_, q_, r_, aq_, ar_;
};

// A point in half texels.
struct HalfPoint {
    i64 x = 0, y = 0;
    friend bool operator==(const HalfPoint&, const HalfPoint&) = default;
};
using HalfPolygon = std::vector<HalfPoint>; // convex, clockwise (y down)

Polygon to_polygon(const HalfPolygon& p, Rect rect);
// The same for vertices in units of 1/scale texel (scale a power of two,
// so the public vertices stay exact).
Polygon to_polygon(const HalfPolygon& p, Rect rect, i64 scale);

// Paper 2.2.1: a maximal run of opaque texels on one row. x1 is inclusive as
// in the paper's FindOpaqueSegments. `down` lists the indices of segments on
// the next row that overlap it, in x order.
struct Segment {
    int x0 = 0, x1 = 0, y = 0;
    std::vector<int> down;
};

// Segments of `mask` at least `min_length` texels long (the paper ignores
// runs shorter than 3), in scan order, with the graph edges of 2.2.1.
std::vector<Segment> find_opaque_segments(const Mask& mask, int min_length);

// The texels an opaque polygon may touch. With Filter::nearest these are the
// opaque texels of the rect. With Filter::linear a texel is safe only when
// its whole 3x3 neighbourhood is opaque (inside the rect): a polygon that is
// valid against this mask keeps at least one texel, so more than the
// required half texel, away from every non-opaque texel square. Conservative
// by half a texel; see docs/opaque.md.
Mask safe_mask(ImageView image, Rect rect, Filter filter);

// Row-wise prefix sums of a 0/1 grid, for O(1) span counts.
class RowSums {
public:
    RowSums() = default;
    explicit RowSums(const Mask& mask, bool count_set = true);
    // Number of counted texels in row y, columns [x0, x1). Columns outside
    // the grid count as `outside` each (and so do rows outside it).
    i64 span(int y, int x0, int x1, i64 outside = 0) const {
        if (x1 <= x0) return 0;
        if (x0 >= 0 && x1 <= width_ && y >= 0 && y < height_) { // the common case
            const std::int32_t* row = &sums_[std::size_t(y) * (width_ + 1)];
            return i64(row[x1]) - row[x0];
        }
        return span_clipped(y, x0, x1, outside);
    }
    int width() const { return width_; }
    int height() const { return height_; }
    // Recounts rows [y0, y1) of a grid built with count_set == true after
    // `mask` changed only there: a greedy step changes a few rows, and
    // rebuilding every row each step was a large share of small images'
    // cost.
    void refresh_rows(const Mask& mask, int y0, int y1) {
        for (int y = y0; y < y1; ++y) {
            std::int32_t* row = &sums_[std::size_t(y) * (width_ + 1)];
            const std::uint8_t* bits = &mask.bits[std::size_t(y) * width_];
            for (int x = 0; x < width_; ++x) row[x + 1] = row[x] + (bits[x] != 0 ? 1 : 0);
        }
    }

private:
    i64 span_clipped(int y, int x0, int x1, i64 outside) const;
    int width_ = 0, height_ = 0;
    std::vector<std::int32_t> sums_; // (width + 1) per row; images hold < 2^31 texels
};

// Texel columns [lo, hi) of row `row` whose closed squares lie inside the
// convex clockwise polygon `p`, whose coordinates are in units of
// 1/`scale` texel (empty when hi <= lo).
void covered_columns(const HalfPolygon& p, int row, i64& lo, i64& hi, i64 scale = 2);

// Texel columns [lo, hi) of row `row` whose open squares meet the open
// interior of the convex clockwise polygon `p` (half texels): the texels it
// touches (empty when hi <= lo). With `margin` > 0: that polygon grown by a
// square of half-side `margin` half texels (its Minkowski sum).
void touched_columns(const HalfPolygon& p, int row, i64& lo, i64& hi, i64 margin = 0);
// The core of touched_columns for a band [y0, y1] (half texels, y0 < y1)
// within the polygon's y extent, for callers that already know the extent.
void band_columns(const HalfPolygon& p, i64 y0, i64 y1, i64 margin, i64& lo, i64& hi);

// A quad with horizontal top and bottom edges, in half texels: top edge
// y = yt from xlt to xrt, bottom edge y = yb from xlb to xrb. Both searches
// produce only these (the paper's "always quadrilaterals"); a zero-width top
// or bottom makes it a triangle.
struct Trapezoid {
    i64 yt = 0, yb = 0, xlt = 0, xrt = 0, xlb = 0, xrb = 0;
    HalfPolygon polygon() const; // clockwise, duplicate vertices dropped
};

// The grid a search runs against: which texels are safe to touch.
struct SafeGrid {
    explicit SafeGrid(const Mask& safe);
    int width, height;
    RowSums unsafe;   // texels outside the grid count as unsafe
    RowSums unsafe_columns; // the same, transposed: columns as rows
    Mask safe_mask;
    bool safe(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height && safe_mask.at(x, y); }
};

// Exact: true when the trapezoid's interior meets no unsafe texel's open
// square and none of its edges runs along an unsafe texel's side (the
// guarantee of analyze.h, with "unsafe" for "non-opaque"). O(rows).
bool trapezoid_valid(const Trapezoid& t, const SafeGrid& grid, i64& work);

// The O(1) part of trapezoid_valid: inside the grid, and no horizontal or
// vertical edge along an unsafe texel. False means trapezoid_valid is false.
bool trapezoid_edges_valid(const Trapezoid& t, const SafeGrid& grid);

// One quad of the paper's FindOpaqueQuadRecursive, before the 0.5 push of
// GenerateOpaquePolygons: integer vertices (x0, y0) (x1, y0) (x2, y1)
// (x3, y1), y1 = next.y + 1.
struct PaperQuad {
    int x0 = 0, x1 = 0, x2 = 0, x3 = 0, y0 = 0, y1 = 0;
    i64 count = 0; // the paper's CountCoveredPixels
};

// One step of FindOpaqueQuadRecursive from `current` to `next` with the
// limiting segments `left`/`right` of the branch from `top`: updates them and
// builds the quad. False when the bottom edge has no width ("no more quads
// on this branch"). Errata applied: `current == top`, the inward-rounded
// x_left.
bool paper_step(const std::vector<Segment>& segments, int top, int current, int next, int& left, int& right,
                PaperQuad& quad);

// The paper's quad pushed in by half a texel on each axis, as emitted.
Trapezoid paper_pushed(const PaperQuad& q);

// Row y's texel span [x0, x1) in CountCoveredPixels / FillCoveredPixels,
// clamped to [0, width). Errata: the offset is (y - vertices[0].y).
void paper_row_span(const PaperQuad& q, int y, int width, int& x0, int& x1);

// sum_{i=0}^{n-1} floor((a i + b) / m) for n >= 0, m > 0, in O(log m).
i64 floor_sum(i64 n, i64 m, i64 a, i64 b);

// The paper's CountCoveredPixels span lengths summed over the quad's rows,
// exact in O(log): an upper bound on its count whatever the map.
i64 paper_span_total(const PaperQuad& q);

// Work counters reported through OpaqueSearchStats.
struct SearchCounters {
    std::int64_t candidates = 0;
    std::int64_t work = 0;
    bool budget_exhausted = false;
};

std::vector<HalfPolygon> paper_opaque_polygons(const Mask& safe, const OpaqueOptions& options, SearchCounters& counters);
std::vector<HalfPolygon> fast_opaque_polygons(const Mask& safe, const OpaqueOptions& options, SearchCounters& counters);
// Texels whose centre lies strictly inside one of the convex polygons
// (vertices in units of 1/scale texel, scale even), each counted once: how
// many of a sprite's pixels the opaque pass draws at 1:1 (issue 25).
i64 centre_covered_texels(const std::vector<HalfPolygon>& polygons, i64 scale = 2);
// The paper's sequence as fast_opaque_polygons replays it: the same polygons
// as paper_opaque_polygons when neither runs out of its budget.
std::vector<HalfPolygon> replay_paper_polygons(const Mask& safe, const OpaqueOptions& options, SearchCounters& counters);
// Seeded growth (grow_search.cpp): polygons and the texels they cover.
struct GrownPolygons {
    std::vector<HalfPolygon> polygons;
    i64 covered = 0; // texel squares inside the polygons
};
// OpaqueMethod::cover (cover_search.cpp): convex pieces of the safe region
// eroded by 1/16 texel, vertices in units of 1/kCoverScale texel.
inline constexpr i64 kCoverScale = 16;
std::vector<HalfPolygon> cover_opaque_polygons(const Mask& safe, const OpaqueOptions& options, SearchCounters& counters);
GrownPolygons grow_opaque_polygons(const SafeGrid& grid, const OpaqueOptions& options, SearchCounters& counters);

// Exact: true when the convex clockwise polygon's interior meets no unsafe
// texel's open square and none of its edges runs along an unsafe texel's
// side. O(rows * vertices).
bool convex_valid(const HalfPolygon& p, const SafeGrid& grid, i64& work);

} // namespace depthcull::opaque_detail
