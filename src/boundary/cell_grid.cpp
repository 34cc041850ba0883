// The occupied-cell grid of paper 2.1 and its sound IsLineEmpty.
//
// The paper samples the segment at unit steps and tests the pixel under each
// sample; its own comment (and the errata) note that a sound test must
// check every pixel the segment touches. Here a segment is tested row by row:
// within one cell row the part of the segment strictly inside the row spans
// an exact rational x-interval, and the occupied runs of that row answer in
// one binary search whether a cell overlaps it.
#include <algorithm>

#include "boundary/boundary_internal.h"

namespace depthcull::boundary {


CellGrid::CellGrid(int width, int height, std::vector<std::vector<Run>> rows) : width_(width), height_(height) {
    row_start_.reserve(std::size_t(height) + 1);
    box_ = {width, height, 0, 0};
    for (int y = 0; y < height; ++y) {
        row_start_.push_back(std::uint32_t(runs_.size()));
        for (const Run& r : rows[std::size_t(y)]) {
            runs_.push_back(r);
            cells_ += r.x1 - r.x0;
            box_.x0 = std::min<std::int64_t>(box_.x0, r.x0);
            box_.x1 = std::max<std::int64_t>(box_.x1, r.x1);
            box_.y0 = std::min<std::int64_t>(box_.y0, y);
            box_.y1 = std::max<std::int64_t>(box_.y1, y + 1);
        }
    }
    row_start_.push_back(std::uint32_t(runs_.size()));
    if (cells_ == 0) box_ = {};
}

bool CellGrid::any_in_row(std::int64_t y, std::int64_t x0, std::int64_t x1) const {
    if (y < 0 || y >= height_ || x0 >= x1) return false;
    const Run* b = row_begin(int(y));
    const Run* e = row_end(int(y));
    // First run ending after x0; it overlaps [x0, x1) when it starts before x1.
    const Run* r = std::upper_bound(b, e, x0, [](std::int64_t v, const Run& run) { return v < run.x1; });
    return r != e && r->x0 < x1;
}

bool CellGrid::occupied(std::int64_t x, std::int64_t y) const { return any_in_row(y, x, x + 1); }

// Some column x in [x0, x1) has both (x, ya) and (x, yb) occupied.
bool CellGrid::both_rows_in_range(std::int64_t ya, std::int64_t yb, std::int64_t x0, std::int64_t x1) const {
    if (ya < 0 || yb < 0 || ya >= height_ || yb >= height_) return false;
    const Run *a = row_begin(int(ya)), *ae = row_end(int(ya));
    const Run *b = row_begin(int(yb)), *be = row_end(int(yb));
    while (a != ae && b != be) {
        std::int64_t lo = std::max<std::int64_t>({a->x0, b->x0, x0});
        std::int64_t hi = std::min<std::int64_t>({a->x1, b->x1, x1});
        if (lo < hi) return true;
        if (a->x1 < b->x1) ++a;
        else ++b;
    }
    return false;
}

bool CellGrid::segment_clear(Pt a, Pt b) const {
    if (a.y == b.y) {
        // Along a grid line: it cuts the union only between two occupied
        // cells stacked across it.
        return !both_rows_in_range(a.y - 1, a.y, std::min(a.x, b.x), std::max(a.x, b.x));
    }
    if (a.y > b.y) std::swap(a, b);
    std::int64_t y_lo = std::max<std::int64_t>(a.y, 0), y_hi = std::min<std::int64_t>(b.y, height_);
    if (a.x == b.x) {
        for (std::int64_t y = y_lo; y < y_hi; ++y)
            if (occupied(a.x - 1, y) && occupied(a.x, y)) return false;
        return true;
    }
    // Slanted: in row y the open part of the segment projects onto the open
    // interval between x(y) and x(y+1); cells overlapping it are crossed.
    // Through a grid vertex the segment enters cell interiors on both sides,
    // so crossing interiors is the only way it can meet the union's interior.
    std::int64_t dx = b.x - a.x, dy = b.y - a.y;
    for (std::int64_t y = y_lo; y < y_hi; ++y) {
        std::int64_t n0 = a.x * dy + (y - a.y) * dx;     // x(y) * dy
        std::int64_t n1 = a.x * dy + (y + 1 - a.y) * dx; // x(y+1) * dy
        std::int64_t lo = std::min(n0, n1), hi = std::max(n0, n1);
        if (any_in_row(y, floor_div(lo, dy), ceil_div(hi, dy))) return false;
    }
    return true;
}

namespace {

// Row runs of non-transparent texels of rect, relative to the rect.
std::vector<std::vector<Run>> texel_runs(ImageView image, Rect rect) {
    std::vector<std::vector<Run>> rows(std::size_t(std::max(rect.h, 0)));
    for (int y = 0; y < rect.h; ++y) {
        const std::uint8_t* row = image.texel(rect.x, rect.y + y);
        int x = 0;
        while (x < rect.w) {
            while (x < rect.w && is_transparent(row[x * 4 + 3])) ++x;
            if (x == rect.w) break;
            int start = x;
            while (x < rect.w && !is_transparent(row[x * 4 + 3])) ++x;
            rows[std::size_t(y)].push_back({start, x});
        }
    }
    return rows;
}

// Union of two sorted, disjoint run lists.
std::vector<Run> merge_runs(const std::vector<Run>& a, const std::vector<Run>& b) {
    std::vector<Run> all;
    all.reserve(a.size() + b.size());
    std::merge(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(all),
               [](const Run& l, const Run& r) { return l.x0 < r.x0; });
    std::vector<Run> out;
    for (const Run& r : all) {
        if (!out.empty() && r.x0 <= out.back().x1) out.back().x1 = std::max(out.back().x1, r.x1);
        else out.push_back(r);
    }
    return out;
}

} // namespace

CellGrid make_cell_grid(ImageView image, Rect rect, Filter filter) {
    if (rect.empty() || !image.contains(rect)) return {};
    std::vector<std::vector<Run>> texels = texel_runs(image, rect);
    if (filter == Filter::nearest) return CellGrid(rect.w, rect.h, std::move(texels));

    // Linear: texel (i, j) grown by half a texel covers half-texel cells
    // [2i-1, 2i+3) x [2j-1, 2j+3), clipped to the rect. Doubled row r is
    // covered by texel rows floor((r-1)/2) and floor((r+1)/2).
    int w2 = 2 * rect.w, h2 = 2 * rect.h;
    std::vector<std::vector<Run>> grown(texels.size());
    for (std::size_t j = 0; j < texels.size(); ++j)
        for (const Run& r : texels[j])
            grown[j].push_back({std::max(2 * r.x0 - 1, 0), std::min(2 * r.x1 + 1, w2)});
    for (auto& row : grown) row = merge_runs(row, {}); // grown runs may now touch
    std::vector<std::vector<Run>> rows(static_cast<std::size_t>(h2));
    for (int r = 0; r < h2; ++r) {
        int ja = (r - 1) >= 0 ? (r - 1) / 2 : -1, jb = (r + 1) / 2;
        std::vector<Run> a = ja >= 0 ? grown[std::size_t(ja)] : std::vector<Run>{};
        const std::vector<Run> empty;
        const std::vector<Run>& b = jb < rect.h && jb != ja ? grown[std::size_t(jb)] : empty;
        rows[std::size_t(r)] = merge_runs(a, b);
    }
    return CellGrid(w2, h2, std::move(rows));
}

} // namespace depthcull::boundary
