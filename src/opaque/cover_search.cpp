// Beyond the paper (issue 25, point 2): OpaqueMethod::cover, the opaque
// texel region covered by as many convex pieces as pay, instead of the
// paper's at most 4 overlapping quads.
//
// The region is the union of the safe texel squares (the mask every method
// searches, opaque_segments.cpp: safe_mask) eroded by kInset = 1/16 texel:
// every point of every piece keeps that distance from every unsafe texel
// square and from the rect's border, which is the guarantee of analyze.h
// with room to spare (no interior meets an unsafe square, no edge runs along
// one). The erosion is small so that a piece covers the *centres* of the
// texels along the outline too (the pixels the opaque pass draws at 1:1),
// which the half-texel push of the paper and of `grow` leave on the edge.
//
// Decomposition, exact on the 1/16-texel grid (kScale):
// 1. Rows split into maximal safe runs. A run continues into the run below
//    when each is the other's only overlapping run: chains of such runs are
//    *stacks*, monotone staircases (a ring splits into its top, its two
//    arms and its bottom).
// 2. A stack's rows [i, j) become one trapezoid whose top and bottom lie on
//    texel rows (inset at the stack's own ends) and whose left and right
//    sides are the straight lines that stay inside the eroded staircase and
//    cover the most area: the staircase's outline simplified inward. Each
//    side is a supporting line of the constraint points (two per row) at
//    the piece's middle height, its ends rounded inward to the grid, so the
//    piece is valid by construction; count_opaque_violations checks it in
//    the tests all the same.
// 3. A piece is split at the row where it loses the most width to the
//    staircase (kept away from its ends, so splits stay balanced) when the
//    two halves are worth more than the whole. A piece is worth its area in
//    texels less `min_area` (OpaqueOptions: what one more polygon must
//    cover to pay for its triangles and edges; the target's cost model sets
//    it, pipeline::plan_target), so the cost model chooses how finely the
//    outline is followed; pieces worth nothing are dropped.
// 4. The `max_polygons` pieces worth the most are kept (ties in scan
//    order); while more pieces pay than that, the cut is made again with
//    the piece cost doubled, and the cut whose kept pieces cover the most
//    wins. `min_coverage` does not stop this method: covering past the
//    paper's 0.75 is its point.
//
// Pieces of one stack meet along texel rows; drawn in one opaque pass at
// one depth they leave no seam at 1:1 (no pixel centre lies on a texel
// row), and the texel margin the scene pulls them in by is a 1/32-texel
// strip. Pieces are quads or triangles: two triangles each.
#include <algorithm>
#include <limits>
#include <numeric>

#include "opaque/opaque_internal.h"

namespace depthcull::opaque_detail {

namespace {

// A safe run of one row, texel columns [x0, x1).
struct Run {
    int x0 = 0, x1 = 0;
};

struct Stack {
    int y0 = 0;            // first row
    std::vector<Run> runs; // one per row from y0
};

struct Piece {
    Trapezoid t;      // in units of 1/kScale texel, relative to the rect
    i64 area2 = 0;    // twice its area, in units^2
    i64 value = 0;    // area in texels less the cost, in units^2
    bool ok = false;
};

constexpr i64 S = kCoverScale;
constexpr i64 kInset = 1; // 1/16 texel

i64 ceil_div_i(i64 a, i64 b) { return -floor_div(-a, b); }

// A line x(y) >= c at every (y, c) of `pts` (sorted by y) with the least
// x at y = mid, evaluated at y0 and y1 and rounded up to the grid (a
// rounded-up end keeps the whole segment above the line). The least value
// at `mid` is the upper concave envelope there; its edge is the line.
void support_line(std::vector<std::pair<i64, i64>>& pts, i64 mid, i64 y0, i64 y1, i64& x0, i64& x1) {
    // Upper hull (max c), monotone chain over y; one point per y (the
    // largest c there).
    std::vector<std::pair<i64, i64>> hull;
    for (const auto& p : pts) {
        if (!hull.empty() && hull.back().first == p.first) {
            if (hull.back().second >= p.second) continue;
            hull.pop_back();
        }
        while (hull.size() >= 2) {
            const auto& a = hull[hull.size() - 2];
            const auto& b = hull.back();
            // Drop b when it lies on or below the chord a -> p.
            const i64 lhs = (b.second - a.second) * (p.first - a.first);
            const i64 rhs = (p.second - a.second) * (b.first - a.first);
            if (lhs <= rhs) hull.pop_back();
            else break;
        }
        hull.push_back(p);
    }
    if (hull.size() == 1) { // not reached: every row gives two heights
        x0 = x1 = hull[0].second;
        return;
    }
    // The hull edge over `mid` (the one starting there when mid is a vertex).
    std::size_t k = 0;
    while (k + 2 < hull.size() && hull[k + 1].first <= mid) ++k;
    const auto a = hull[k], b = hull[k + 1];
    const i64 dy = b.first - a.first, dc = b.second - a.second;
    x0 = a.second + ceil_div_i(dc * (y0 - a.first), dy);
    x1 = a.second + ceil_div_i(dc * (y1 - a.first), dy);
}

class CoverSearch {
public:
    CoverSearch(const Stack& s, i64 cost, SearchCounters& counters) : s_(s), cost_(cost), counters_(counters) {}

    // The best pieces for rows [i, j) of the stack (appended to `out`) and
    // their summed value.
    i64 best(int i, int j, std::vector<Piece>& out) {
        Piece whole = piece(i, j);
        const int n = j - i;
        i64 whole_value = whole.ok ? std::max<i64>(whole.value, 0) : 0;
        if (n == 1) {
            if (whole.ok && whole.value > 0) out.push_back(whole);
            return whole_value;
        }
        // Width lost to the staircase, per row (at the row's middle).
        i64 lost_total = 0, worst = -1;
        int split = i + n / 2;
        if (whole.ok) {
            for (int k = i; k < j; ++k) {
                const Run r = s_.runs[std::size_t(k)];
                const i64 row_width = (i64(r.x1) - r.x0) * S - 2 * kInset;
                const i64 ym2 = 2 * ((i64(s_.y0) + k) * S) + S; // twice the row's middle
                // Trapezoid width at the middle height, times 2 (t.yb - t.yt).
                const Trapezoid& t = whole.t;
                const i64 h = t.yb - t.yt;
                const i64 wt = t.xrt - t.xlt, wb = t.xrb - t.xlb;
                const i64 w2h = wt * (2 * t.yb - ym2) + wb * (ym2 - 2 * t.yt); // width * 2h
                const i64 lost = row_width * 2 * h - w2h;                      // times 2h
                lost_total += lost / (2 * h) * S;
                if (lost > worst) worst = lost, split = k;
            }
            // Splitting adds a piece: not worth trying when all it could win
            // back is under that piece's cost.
            if (lost_total <= cost_) {
                out.push_back(whole);
                return whole_value;
            }
            const int quarter = std::max(1, n / 4);
            split = std::clamp(split, i + quarter, j - quarter);
        }
        counters_.work += n;
        std::vector<Piece> parts;
        const i64 parts_value = best(i, split, parts) + best(split, j, parts);
        if (whole.ok && whole.value > 0 && whole_value >= parts_value) {
            out.push_back(whole);
            return whole_value;
        }
        out.insert(out.end(), parts.begin(), parts.end());
        return parts_value;
    }

private:
    // The trapezoid of rows [i, j): sides from support_line against two
    // constraint points per row (each row's run, eroded, holds over the
    // row's band grown by the inset); the rows just outside join in where
    // the piece ends on a row inside the stack (it meets them there).
    Piece piece(int i, int j) {
        ++counters_.candidates;
        const int n = int(s_.runs.size());
        const bool top_end = i == 0, bottom_end = j == n;
        const i64 yt = (i64(s_.y0) + i) * S + (top_end ? kInset : 0);
        const i64 yb = (i64(s_.y0) + j) * S - (bottom_end ? kInset : 0);
        left_.clear(), right_.clear();
        for (int k = top_end ? i : i - 1; k <= (bottom_end ? j - 1 : j); ++k) {
            const i64 lo = std::max((i64(s_.y0) + k) * S - kInset, yt);
            const i64 hi = std::min((i64(s_.y0) + k + 1) * S + kInset, yb);
            const Run r = s_.runs[std::size_t(k)];
            const i64 left = i64(r.x0) * S + kInset, right = i64(r.x1) * S - kInset;
            // x >= left; -x >= -right.
            left_.push_back({lo, left}), left_.push_back({hi, left});
            right_.push_back({lo, -right}), right_.push_back({hi, -right});
        }
        counters_.work += i64(left_.size());
        auto by_y = [](const auto& a, const auto& b) { return a < b; };
        std::sort(left_.begin(), left_.end(), by_y);
        std::sort(right_.begin(), right_.end(), by_y);
        const i64 mid2 = yt + yb; // twice the middle; compared with 2y below
        Piece p;
        i64 xlt, xlb, nxrt, nxrb;
        for (auto& v : left_) v.first *= 2;
        for (auto& v : right_) v.first *= 2;
        support_line(left_, mid2, 2 * yt, 2 * yb, xlt, xlb);
        support_line(right_, mid2, 2 * yt, 2 * yb, nxrt, nxrb);
        const i64 xrt = -nxrt, xrb = -nxrb;
        if (xlt > xrt || xlb > xrb || (xlt == xrt && xlb == xrb)) return p; // the sides cross: no trapezoid
        p.t = {yt, yb, xlt, xrt, xlb, xrb};
        p.area2 = (yb - yt) * ((xrt - xlt) + (xrb - xlb));
        p.value = p.area2 / 2 - cost_;
        p.ok = true;
        return p;
    }

    const Stack& s_;
    i64 cost_;
    SearchCounters& counters_;
    std::vector<std::pair<i64, i64>> left_, right_;
};

std::vector<Stack> find_stacks(const Mask& safe) {
    std::vector<std::vector<Run>> rows(std::size_t(safe.height));
    for (int y = 0; y < safe.height; ++y)
        for (int x = 0; x < safe.width;) {
            if (!safe.at(x, y)) {
                ++x;
                continue;
            }
            int x1 = x;
            while (x1 < safe.width && safe.at(x1, y)) ++x1;
            rows[std::size_t(y)].push_back({x, x1});
            x = x1;
        }
    // below[y][r]: the only run of row y + 1 that run r overlaps, or -1
    // (none or several); above likewise.
    auto overlaps = [](Run a, Run b) { return std::max(a.x0, b.x0) < std::min(a.x1, b.x1); };
    std::vector<std::vector<int>> below(rows.size()), above(rows.size());
    for (std::size_t y = 0; y < rows.size(); ++y) {
        below[y].assign(rows[y].size(), -1);
        above[y].assign(rows[y].size(), -1);
    }
    for (std::size_t y = 0; y + 1 < rows.size(); ++y) {
        std::vector<int> down_count(rows[y].size(), 0), up_count(rows[y + 1].size(), 0);
        // Both rows' runs are sorted: a merge walk finds the overlaps.
        std::size_t a = 0, b = 0;
        while (a < rows[y].size() && b < rows[y + 1].size()) {
            const Run ra = rows[y][a], rb = rows[y + 1][b];
            if (overlaps(ra, rb)) {
                ++down_count[a], ++up_count[b];
                below[y][a] = int(b), above[y + 1][b] = int(a);
            }
            if (ra.x1 <= rb.x1) ++a;
            else ++b;
        }
        for (std::size_t r = 0; r < rows[y].size(); ++r)
            if (down_count[r] != 1) below[y][r] = -1;
        for (std::size_t r = 0; r < rows[y + 1].size(); ++r)
            if (up_count[r] != 1) above[y + 1][r] = -1;
    }
    std::vector<Stack> stacks;
    for (std::size_t y = 0; y < rows.size(); ++y)
        for (std::size_t r = 0; r < rows[y].size(); ++r) {
            // A stack starts at a run that does not continue one above.
            const int up = above[y][r];
            if (up >= 0 && below[y - 1][std::size_t(up)] == int(r)) continue;
            Stack s;
            s.y0 = int(y);
            std::size_t yy = y, rr = r;
            for (;;) {
                s.runs.push_back(rows[yy][rr]);
                const int down = below[yy][rr];
                if (down < 0 || above[yy + 1][std::size_t(down)] != int(rr)) break;
                ++yy, rr = std::size_t(down);
            }
            stacks.push_back(std::move(s));
        }
    return stacks;
}

} // namespace

std::vector<HalfPolygon> cover_opaque_polygons(const Mask& safe, const OpaqueOptions& options,
                                               SearchCounters& counters) {
    std::vector<HalfPolygon> result;
    if (options.max_polygons <= 0) return result;
    const std::vector<Stack> stacks = find_stacks(safe);
    // A piece must cover min_area texels to pay (at least one: a piece of
    // no area never pays), in units^2. When more pieces pay than
    // max_polygons allows, the finest cut keeps only its largest pieces,
    // which may cover less than a coarser cut's: the cost is doubled while
    // too many pieces pay, and the cut whose kept pieces cover the most
    // wins (the least cost on ties).
    const std::size_t cap = std::size_t(options.max_polygons);
    i64 cost = std::max<i64>(1, options.min_area) * S * S;
    std::vector<Piece> best;
    i64 best_area = -1;
    for (int round = 0; round < 12; ++round, cost *= 2) {
        std::vector<Piece> pieces;
        for (const Stack& s : stacks) {
            CoverSearch search(s, cost, counters);
            search.best(0, int(s.runs.size()), pieces);
        }
        pieces.erase(std::remove_if(pieces.begin(), pieces.end(), [](const Piece& p) { return !p.ok || p.value <= 0; }),
                     pieces.end());
        // The most valuable first; ties in scan order (stable).
        std::stable_sort(pieces.begin(), pieces.end(), [](const Piece& a, const Piece& b) { return a.value > b.value; });
        const bool over = pieces.size() > cap;
        if (over) pieces.resize(cap);
        i64 area = 0;
        for (const Piece& p : pieces) area += p.area2;
        if (area > best_area) best_area = area, best = std::move(pieces);
        if (!over) break;
    }
    for (const Piece& p : best) result.push_back(p.t.polygon());
    return result;
}

} // namespace depthcull::opaque_detail
