// Ours: opaque polygons grown from seeds (OpaqueMethod::grow, and the first
// half of OpaqueMethod::fast). Paper section 4, caveat 3 suggests it:
// "starting with a small, trivial opaque polygon and pushing the vertices
// outward ... until the polygon's edges reach the boundary".
//
// Each greedy step:
// - seeds: the kSeeds largest maximal rectangles of uncovered texels whose
//   four neighbours are safe (largest rectangle in a histogram, O(w h)); with
//   integer edges such a rectangle covers every texel in it;
// - growth: the best of three kinds of move is applied until none gains a
//   texel: slide a vertex outward along either adjacent edge's line, or
//   (below kMaxOpaqueVertices) put a new vertex on an edge and push it out
//   along the edge's normal, if that gains min_area / 2 texels (a vertex
//   costs a triangle, half a quad's). Each move adds one triangle, and the triangles
//   of a move are nested in its step count, so the largest valid step is
//   found by a doubling then binary search over exact validity checks
//   (convex_valid). Convexity limits every step exactly (integer turns);
// - the grown seed covering the most uncovered texel squares wins and its
//   edges are pushed outward, parallel, while they stay valid: out to about
//   half a texel from the unsafe texels, like the paper's push (the same
//   squares, more pixels when magnified, no extra vertex); the step
//   stops the loop when its polygon reaches fewer than min_area safe texels
//   no earlier polygon reached, where a polygon reaches the texels it
//   touches once grown by half a texel in x and y. For the paper's pushed
//   quads those are exactly the texels it counts (its quad before the
//   push), so the same limit means the same thing for both searches.
//
// Why it is fast: no candidate family of O(N h) quads. A step is O(w h) for
// the seeds plus O(moves * log(range) * rows) for the growth. Why it covers
// more: polygons of up to 8 vertices follow round and sloped outlines, and
// edges may lie on grid lines. It is a heuristic: on 29 of the 953 pingus
// sprites it covers less than the paper's sequence, which is why `fast`
// also replays the paper (fast_search.cpp) and keeps the better.
#include <algorithm>
#include <limits>
#include <numeric>

#include "opaque/opaque_internal.h"

namespace depthcull::opaque_detail {

namespace {

i64 cross(i64 ax, i64 ay, i64 bx, i64 by) { return ax * by - ay * bx; }
// > 0: a -> b -> c turns clockwise on screen (y down), as our polygons do.
i64 turn(HalfPoint a, HalfPoint b, HalfPoint c) { return cross(b.x - a.x, b.y - a.y, c.x - b.x, c.y - b.y); }

HalfPoint primitive(i64 dx, i64 dy) {
    i64 g = std::gcd(dx < 0 ? -dx : dx, dy < 0 ? -dy : dy);
    if (g == 0) return {0, 0};
    return {dx / g, dy / g};
}

} // namespace

bool convex_valid(const HalfPolygon& p, const SafeGrid& g, i64& work) {
    const std::size_t n = p.size();
    if (n < 3) return false;
    i64 xmin = p[0].x, xmax = p[0].x, ymin = p[0].y, ymax = p[0].y;
    for (const auto& v : p) {
        xmin = std::min(xmin, v.x), xmax = std::max(xmax, v.x);
        ymin = std::min(ymin, v.y), ymax = std::max(ymax, v.y);
    }
    if (xmin < 0 || ymin < 0 || xmax > 2 * i64(g.width) || ymax > 2 * i64(g.height) || ymax <= ymin) return false;
    // Edges on grid lines must not run along an unsafe texel's side; the
    // texels on their inner side are checked with the interior below.
    for (std::size_t k = 0; k < n; ++k) {
        const HalfPoint a = p[k], b = p[(k + 1) % n];
        if (a.y == b.y && a.y % 2 == 0 && a.x != b.x) {
            // Clockwise on screen: moving right the inside is below.
            const i64 row = a.x < b.x ? a.y / 2 - 1 : a.y / 2;
            if (g.unsafe.span(int(row), int(floor_div(std::min(a.x, b.x), 2)), int(ceil_div(std::max(a.x, b.x), 2)), 1))
                return false;
        } else if (a.x == b.x && a.x % 2 == 0 && a.y != b.y) {
            const i64 column = a.y < b.y ? a.x / 2 : a.x / 2 - 1;
            if (g.unsafe_columns.span(int(column), int(floor_div(std::min(a.y, b.y), 2)),
                                      int(ceil_div(std::max(a.y, b.y), 2)), 1))
                return false;
        }
    }
    // Interior: no unsafe texel's open square may meet it.
    const i64 row0 = floor_div(ymin, 2), row1 = ceil_div(ymax, 2);
    work += (row1 - row0) * i64(n);
    for (i64 row = row0; row < row1; ++row) {
        // touched_columns without finding the extent again for every row.
        i64 lo, hi;
        band_columns(p, std::max(2 * row, ymin), std::min(2 * row + 2, ymax), 0, lo, hi);
        if (hi > lo && g.unsafe.span(int(row), int(lo), int(hi), 1) != 0) return false;
    }
    return true;
}

namespace {

class GrowSearch {
public:
    GrowSearch(const SafeGrid& grid, int min_area, SearchCounters& counters)
        : grid_(grid), counters_(counters), min_area_(min_area) {
        const Mask& safe = grid.safe_mask;
        interior_ = safe;
        for (int y = 0; y < safe.height; ++y)
            for (int x = 0; x < safe.width; ++x)
                interior_.bits[std::size_t(y) * safe.width + x] =
                    grid_.safe(x, y) && grid_.safe(x - 1, y) && grid_.safe(x + 1, y) && grid_.safe(x, y - 1) &&
                    grid_.safe(x, y + 1);
        uncovered_ = RowSums(interior_);
        unreached_ = safe;
        unreached_sums_ = RowSums(unreached_);
    }

    GrownPolygons run(const OpaqueOptions& options) {
        GrownPolygons result;
        std::vector<HalfPolygon>& out = result.polygons;
        const i64 safe_texels = std::count(grid_.safe_mask.bits.begin(), grid_.safe_mask.bits.end(), 1);
        if (safe_texels == 0) return result;
        i64& covered = result.covered;
        while (int(out.size()) < options.max_polygons && double(covered) / double(safe_texels) < options.min_coverage) {
            std::vector<TexelBox> seeds = largest_rectangles();
            if (seeds.empty()) break;
            // Grown seeds by texel squares, most first (earlier seed on ties).
            std::vector<std::pair<i64, HalfPolygon>> grown;
            for (const TexelBox& r : seeds) {
                HalfPolygon q = {{2 * i64(r.x0), 2 * i64(r.y0)},
                                 {2 * i64(r.x1), 2 * i64(r.y0)},
                                 {2 * i64(r.x1), 2 * i64(r.y1)},
                                 {2 * i64(r.x0), 2 * i64(r.y1)}};
                grow(q, false);
                grown.emplace_back(count_inside(q, 0, grid_.height), std::move(q));
            }
            std::stable_sort(grown.begin(), grown.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
            // Only the one kept is inflated: the second phase adds no squares.
            HalfPolygon p;
            i64 c = 0;
            for (auto& [cq, q] : grown) {
                if (cq < 1) break;
                grow(q, true);
                if (count_reached(q) >= options.min_area) {
                    c = cq, p = std::move(q);
                    break;
                }
            }
            if (c < 1) break;
            covered += c;
            mark(p);
            out.push_back(std::move(p));
        }
        return result;
    }

private:
    struct TexelBox {
        int x0, y0, x1, y1;
    };

    // Calls f(y, lo, hi) for rows [r0, r1) with the polygon's columns in
    // row y (covered_columns or reached), clamped to the grid.
    template <class Columns, class F>
    void for_rows(const HalfPolygon& p, i64 r0, i64 r1, Columns columns, F f) const {
        r0 = std::max<i64>(r0, 0), r1 = std::min<i64>(r1, grid_.height);
        for (i64 y = r0; y < r1; ++y) {
            i64 lo, hi;
            columns(p, int(y), lo, hi);
            lo = std::max<i64>(lo, 0), hi = std::min<i64>(hi, grid_.width);
            if (hi > lo) f(int(y), int(lo), int(hi));
        }
    }
    static void squares(const HalfPolygon& p, int y, i64& lo, i64& hi) { covered_columns(p, y, lo, hi); }

    // Uncovered interior texels whose closed squares lie inside p, rows [r0, r1).
    i64 count_inside(const HalfPolygon& p, i64 r0, i64 r1) const {
        i64 n = 0;
        for_rows(p, r0, r1, squares, [&](int y, int lo, int hi) { n += uncovered_.span(y, lo, hi); });
        counters_.work += std::max<i64>(0, std::min<i64>(r1, grid_.height) - std::max<i64>(r0, 0));
        return n;
    }

    // The texels p reaches: those it touches once grown by half a texel in
    // x and y. That is the paper's count for its quads (their texels before
    // the half-texel push, i.e. the pushed quad grown back) and about the
    // same for ours, so one stop rule means the same for both searches.
    static void reached(const HalfPolygon& p, int y, i64& lo, i64& hi) { touched_columns(p, y, lo, hi, 1); }

    // Safe texels p reaches that no earlier polygon reached (the stop rule).
    i64 count_reached(const HalfPolygon& p) const {
        i64 n = 0;
        for_rows(p, 0, grid_.height, reached, [&](int y, int lo, int hi) { n += unreached_sums_.span(y, lo, hi); });
        return n;
    }

    // Takes p's texels out of what later polygons can gain.
    void mark(const HalfPolygon& p) {
        clear_rows(p, reached, unreached_, unreached_sums_);
        clear_rows(p, squares, interior_, uncovered_);
    }
    template <class Columns>
    void clear_rows(const HalfPolygon& p, Columns columns, Mask& mask, RowSums& sums) {
        for_rows(p, 0, grid_.height, columns, [&](int y, int lo, int hi) {
            std::fill_n(mask.bits.begin() + std::ptrdiff_t(std::size_t(y) * grid_.width + std::size_t(lo)), hi - lo, 0);
            sums.refresh_rows(mask, y, y + 1);
        });
    }

    // One way to push the polygon outward: the triangle it adds, as a
    // function of a step count k along an integer direction, nested in k.
    struct Move {
        int kind = 0;   // 0 slide vertex forward, 1 slide backward, 2 insert on edge, 3 push edge
        int index = 0;  // vertex (slides) or edge start (insert, push)
        HalfPoint base, dir;
        HalfPoint dir2; // push: the edge's end moves by k dir2 as its start moves by k dir
        i64 k = 0;      // the largest valid step
        i64 gain = 0;   // new texels
        i64 area2 = 0;  // doubled area added, half units
    };

    static HalfPoint at(const HalfPolygon& p, int i) {
        const int n = int(p.size());
        return p[std::size_t(((i % n) + n) % n)];
    }

    static HalfPoint step(HalfPoint b, HalfPoint d, i64 k) { return {b.x + k * d.x, b.y + k * d.y}; }

    // The polygon after the move with step k.
    static HalfPolygon apply(const HalfPolygon& p, const Move& m, i64 k) {
        HalfPolygon q = p;
        const HalfPoint c = step(m.base, m.dir, k);
        if (m.kind < 2) q[std::size_t(m.index)] = c;
        else if (m.kind == 2) q.insert(q.begin() + m.index + 1, c);
        else q[std::size_t(m.index)] = c, q[std::size_t((m.index + 1) % int(p.size()))] = step(at(p, m.index + 1), m.dir2, k);
        // Drop vertices the move made straight.
        for (bool again = true; again && q.size() > 3;) {
            again = false;
            for (std::size_t i = 0; i < q.size() && q.size() > 3; ++i) {
                const std::size_t n = q.size();
                if (turn(q[(i + n - 1) % n], q[i], q[(i + 1) % n]) == 0) {
                    q.erase(q.begin() + std::ptrdiff_t(i));
                    again = true;
                    break;
                }
            }
        }
        return q;
    }

    // The region the move adds, clockwise: a triangle, or for a push the
    // trapezoid between the edge and its parallel.
    static HalfPolygon added(const HalfPolygon& p, const Move& m, i64 k) {
        const HalfPoint c = step(m.base, m.dir, k);
        const HalfPoint v = at(p, m.index), w = at(p, m.index + 1);
        if (m.kind == 1) return {at(p, m.index - 1), c, v};
        if (m.kind == 3) {
            const HalfPoint d = step(w, m.dir2, k);
            if (d.x == c.x && d.y == c.y) return {c, w, v}; // the edge shrank to a point
            return {c, d, w, v};
        }
        return {v, c, w};
    }
    static i64 area2(const HalfPolygon& p) {
        i64 a = 0;
        for (std::size_t i = 0, n = p.size(); i < n; ++i) a += cross(p[i].x, p[i].y, p[(i + 1) % n].x, p[(i + 1) % n].y);
        return a;
    }

    bool valid_step(const HalfPolygon& p, const Move& m, i64 k) {
        return convex_valid(added(p, m, k), grid_, counters_.work);
    }

    // Largest k in [1, kmax] whose added region is valid (0 if none).
    i64 largest_step(const HalfPolygon& p, const Move& m, i64 kmax) {
        if (kmax < 1 || !valid_step(p, m, 1)) return 0;
        i64 good = 1, bad = kmax + 1;
        for (i64 k = 2; k <= kmax; k *= 2) {
            if (valid_step(p, m, k)) good = k;
            else {
                bad = k;
                break;
            }
        }
        if (bad == kmax + 1 && good < kmax) {
            if (valid_step(p, m, kmax)) return kmax;
            bad = kmax;
        }
        while (bad - good > 1) {
            const i64 mid = good + (bad - good) / 2;
            if (valid_step(p, m, mid)) good = mid;
            else bad = mid;
        }
        return good;
    }

    // kmax so that base + k dir stays inside the grid's box.
    i64 box_limit(HalfPoint b, HalfPoint d) const {
        i64 k = std::numeric_limits<std::int32_t>::max();
        auto limit = [&](i64 pos, i64 step, i64 hi) {
            if (step > 0) k = std::min(k, (hi - pos) / step);
            else if (step < 0) k = std::min(k, pos / -step);
        };
        limit(b.x, d.x, 2 * i64(grid_.width));
        limit(b.y, d.y, 2 * i64(grid_.height));
        return k;
    }
    // A <= k B style limit from a convexity condition A + k B >= 0.
    static void keep(i64& kmax, i64 a, i64 b) {
        if (b < 0) kmax = std::min(kmax, a >= 0 ? a / -b : -1);
        else if (a < 0) kmax = -1;
    }

    void evaluate(const HalfPolygon& p, Move& m) {
        const int i = m.index;
        const HalfPoint v = at(p, i);
        i64 kmax = box_limit(m.base, m.dir);
        const HalfPoint d = m.dir;
        if (m.kind == 0) { // v + k d, d along u -> v; keep turn(v', w, x) >= 0
            const HalfPoint w = at(p, i + 1), x = at(p, i + 2);
            keep(kmax, turn(v, w, x), -cross(d.x, d.y, x.x - w.x, x.y - w.y));
        } else if (m.kind == 1) { // d along w -> v; keep turn(t, u, v') >= 0
            const HalfPoint u = at(p, i - 1), t = at(p, i - 2);
            keep(kmax, turn(t, u, v), cross(u.x - t.x, u.y - t.y, d.x, d.y));
        } else if (m.kind == 3) { // v + k d, w + k dir2, the edge keeps its direction: keep its length >= 0
            const HalfPoint w = at(p, i + 1), e{w.x - v.x, w.y - v.y};
            kmax = std::min(kmax, box_limit(w, m.dir2));
            keep(kmax, e.x * e.x + e.y * e.y, (m.dir2.x - d.x) * e.x + (m.dir2.y - d.y) * e.y);
        } else { // c = base + k d on edge (a = v, b); keep turn(t, a, c) and turn(c, b, x) >= 0
            const HalfPoint b = at(p, i + 1), t = at(p, i - 1), x = at(p, i + 2);
            keep(kmax, cross(v.x - t.x, v.y - t.y, m.base.x - v.x, m.base.y - v.y), cross(v.x - t.x, v.y - t.y, d.x, d.y));
            keep(kmax, cross(b.x - m.base.x, b.y - m.base.y, x.x - b.x, x.y - b.y), -cross(d.x, d.y, x.x - b.x, x.y - b.y));
        }
        m.k = largest_step(p, m, kmax);
        if (m.k == 0) return;
        const HalfPolygon t = added(p, m, m.k);
        m.area2 = area2(t);
        i64 ymin = t[0].y, ymax = t[0].y;
        for (const HalfPoint& c : t) ymin = std::min(ymin, c.y), ymax = std::max(ymax, c.y);
        HalfPolygon q = apply(p, m, m.k);
        m.gain = count_inside(q, floor_div(ymin, 2), ceil_div(ymax, 2)) -
                 count_inside(p, floor_div(ymin, 2), ceil_div(ymax, 2));
    }

    // Applies the best move until none is left: by new texel squares (then
    // area), or with by_area, once no move gains a square, only edge pushes
    // by area. That second phase keeps the shape and the vertex count (a
    // vertex costs a triangle) and takes the polygon out to about half a
    // texel from the unsafe texels, as the paper's push does: the same
    // squares at 1:1, more of the sprite's pixels when it is drawn magnified.
    void grow(HalfPolygon& p, bool by_area) {
        for (int iteration = 0; iteration < 8 * kMaxOpaqueVertices; ++iteration) {
            Move best;
            const int n = int(p.size());
            auto consider = [&](Move m) {
                if (m.dir.x == 0 && m.dir.y == 0) return;
                evaluate(p, m);
                if (m.k == 0) return;
                // A new vertex costs a triangle, half of what a quad costs,
                // so it must gain half of what a polygon must (min_area):
                // the worth-it rule of docs/opaque.md per vertex. Without it
                // the polygons carried 20% more triangles on the pingus
                // sprites for 0.18% more texels.
                if (m.kind == 2 && 2 * m.gain < min_area_) return;
                const bool better = by_area ? m.area2 > best.area2
                                            : m.gain > best.gain || (m.gain == best.gain && m.area2 > best.area2);
                if (better) best = m;
            };
            for (int i = 0; i < n; ++i) {
                const HalfPoint u = at(p, i - 1), v = at(p, i), w = at(p, i + 1), x = at(p, i + 2);
                const HalfPoint e = primitive(w.x - v.x, w.y - v.y);
                const HalfPoint a = primitive(v.x - u.x, v.y - u.y), b = primitive(w.x - x.x, w.y - x.y);
                if (!by_area) {
                    consider({0, i, v, a, {}});
                    consider({1, i, v, primitive(-e.x, -e.y), {}});
                    if (n < kMaxOpaqueVertices) {
                        const i64 g = e.x != 0 ? (w.x - v.x) / e.x : (w.y - v.y) / e.y;
                        const HalfPoint base{v.x + e.x * (g / 2), v.y + e.y * (g / 2)};
                        consider({2, i, base, primitive(e.y, -e.x), {}});
                    }
                }
                // Push edge v w outward, parallel: v slides along u v (a), w
                // along x w (b), in the ratio that keeps the direction. Both
                // crosses are > 0 on a convex clockwise polygon.
                const i64 ca = cross(a.x, a.y, e.x, e.y), cb = cross(b.x, b.y, e.x, e.y);
                if (ca > 0 && cb > 0) {
                    const i64 g = std::gcd(ca, cb);
                    consider({3, i, v, {a.x * (cb / g), a.y * (cb / g)}, {b.x * (ca / g), b.y * (ca / g)}});
                }
            }
            if (best.k == 0 || (!by_area && best.gain <= 0)) break;
            p = apply(p, best, best.k);
        }
    }

    static i64 overlap(const TexelBox& a, const TexelBox& b) {
        const i64 w = std::min(a.x1, b.x1) - std::max(a.x0, b.x0), h = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
        return w > 0 && h > 0 ? w * h : 0;
    }
    static i64 area(const TexelBox& a) { return i64(a.x1 - a.x0) * (a.y1 - a.y0); }

    // The kSeeds largest maximal rectangles of uncovered interior texels
    // that do not mostly overlap a larger one.
    static constexpr std::size_t kSeeds = 3;
    void offer_seed(std::vector<TexelBox>& kept, const TexelBox& r) const {
        const i64 a = area(r);
        if (kept.size() == kSeeds && a <= area(kept.back())) return;
        for (std::size_t i = 0; i < kept.size(); ++i) {
            if (2 * overlap(kept[i], r) < std::min(a, area(kept[i]))) continue;
            if (area(kept[i]) >= a) return; // a larger one holds most of it
            kept.erase(kept.begin() + std::ptrdiff_t(i--));
        }
        auto at = std::find_if(kept.begin(), kept.end(), [&](const TexelBox& k) { return area(k) < a; });
        kept.insert(at, r);
        if (kept.size() > kSeeds) kept.pop_back();
    }

    std::vector<TexelBox> largest_rectangles() {
        const int w = grid_.width, h = grid_.height;
        std::vector<int> height(std::size_t(w), 0), stack;
        std::vector<TexelBox> kept;
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x)
                height[std::size_t(x)] = interior_.bits[std::size_t(y) * w + x] ? height[std::size_t(x)] + 1 : 0;
            stack.clear();
            for (int x = 0; x <= w; ++x) {
                const int hx = x < w ? height[std::size_t(x)] : 0;
                while (!stack.empty() && height[std::size_t(stack.back())] >= hx) {
                    const int hh = height[std::size_t(stack.back())];
                    stack.pop_back();
                    const int left = stack.empty() ? 0 : stack.back() + 1;
                    if (hh > 0 && hh > hx) offer_seed(kept, {left, y + 1 - hh, x, y + 1});
                }
                stack.push_back(x);
            }
        }
        counters_.work += i64(w) * h;
        return kept;
    }

    const SafeGrid& grid_;
    SearchCounters& counters_;
    int min_area_; // options.min_area: what a polygon must reach, twice what a vertex must gain
    Mask interior_; // interior texels not yet covered
    RowSums uncovered_;
    Mask unreached_; // safe texels no polygon reaches yet
    RowSums unreached_sums_;
};

} // namespace

GrownPolygons grow_opaque_polygons(const SafeGrid& grid, const OpaqueOptions& options, SearchCounters& counters) {
    return GrowSearch(grid, options.min_area, counters).run(options);
}

} // namespace depthcull::opaque_detail
