// The fast opaque-polygon search (OpaqueMethod::fast, the default): the
// polygons grown by grow_search.cpp, guarded by a cheap replay of the
// paper's own greedy sequence; the one covering more texels wins, so the
// result never covers less than the paper's. docs/opaque.md has the design
// and the figures.
//
// The replay computes exactly what paper_quad_search.cpp chooses, faster:
// - the quads are enumerated once, not once per polygon, visiting each
//   (top, left, right, current) state once where the paper re-walks every
//   path of the segment graph (its exponential part);
// - counts take O(rows) with row prefix sums, not O(area) (2.2.2);
// - lazy greedy, best first: one heap of upper bounds (exact floor sums,
//   then band counts from 2D prefix sums) for all steps, so only quads that
//   could still win are counted;
// - a value or bound from an earlier step is reused while no quad chosen
//   since touched the quad's box;
// - after a large quad, the quads it touched get an O(1) box bound and the
//   heap is rebuilt once, instead of one pop and sift per quad; the band
//   bound uses a reciprocal instead of divisions;
// - the per-step masks and prefix sums are updated where the new quad lies
//   instead of rebuilt;
// - a work budget (kFastOpaqueWorkBudget) bounds the worst case.
#include <algorithm>
#include <cmath>

#include "opaque/opaque_internal.h"

namespace depthcull::opaque_detail {

namespace {

// 2D prefix sums of a 0/1 grid: O(1) counts over boxes, for the bounds.
class BoxSums {
public:
    explicit BoxSums(const Mask& m) : w_(m.width), h_(m.height), s_(std::size_t(w_ + 1) * (h_ + 1), 0) {
        for (int y = 0; y < h_; ++y)
            for (int x = 0; x < w_; ++x)
                at(x + 1, y + 1) = at(x, y + 1) + at(x + 1, y) - at(x, y) + (m.bits[std::size_t(y) * w_ + x] != 0);
    }
    // Recomputes the sums after `m` changed only in rows >= y0 (every sum
    // below that row depends on it).
    void refresh_from(const Mask& m, int y0) {
        for (int y = std::max(y0, 0); y < h_; ++y)
            for (int x = 0; x < w_; ++x)
                at(x + 1, y + 1) = at(x, y + 1) + at(x + 1, y) - at(x, y) + (m.bits[std::size_t(y) * w_ + x] != 0);
    }
    // Set texels in [x0, x1) x [y0, y1), clamped to the grid.
    i64 box(int x0, int y0, int x1, int y1) const {
        x0 = std::clamp(x0, 0, w_), x1 = std::clamp(x1, 0, w_);
        y0 = std::clamp(y0, 0, h_), y1 = std::clamp(y1, 0, h_);
        if (x1 <= x0 || y1 <= y0) return 0;
        return get(x1, y1) - get(x0, y1) - get(x1, y0) + get(x0, y0);
    }

private:
    std::int32_t& at(int x, int y) { return s_[std::size_t(y) * (w_ + 1) + x]; }
    i64 get(int x, int y) const { return s_[std::size_t(y) * (w_ + 1) + x]; }
    int w_, h_;
    std::vector<std::int32_t> s_; // counts < 2^31: images hold at most 2^28 texels
};

// Texels [x0, x1) x [y0, y1).
struct TexelBox {
    int x0, y0, x1, y1;
    bool meets(const TexelBox& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

// A quad of the paper's family, stored compactly (image sides <= 16384).
struct StoredQuad {
    std::int16_t x0, x1, x2, x3, y0, y1;
    PaperQuad quad() const { return {x0, x1, x2, x3, y0, y1, 0}; }
    // Every texel any count or bound of this quad reads: its realizations
    // lie inside the integer quad, and the paper's row spans and the band
    // boxes lie between its sides.
    TexelBox box() const { return {std::min(x0, x3), y0, std::max(x1, x2), y1}; }
};

// Best-first order: larger bound first, then earlier quad, packed into one
// integer (bound above, complemented index below) so that the heap compares
// and moves 8 bytes: the heap is most of the cost on solid shapes, where
// every quad is popped once per step.
using Key = std::uint64_t;
inline Key make_key(i64 bound, int index) { return Key(bound) << 32 | Key(~std::uint32_t(index)); }
inline int key_index(Key k) { return int(~std::uint32_t(k)); }

// A 4-ary max-heap of keys with an in-place update of the top: the lazy
// greedy mostly lowers the top's bound, which is one sift-down here instead
// of a pop and a push. Four children share a cache line.
class KeyHeap {
public:
    void assign(std::vector<Key>&& keys) {
        v_ = std::move(keys);
        for (std::size_t i = (v_.size() + 2) / 4; i-- > 0;) sift_down(i, v_[i]);
    }
    bool empty() const { return v_.empty(); }
    Key top() const { return v_.front(); }
    void pop() {
        Key last = v_.back();
        v_.pop_back();
        if (!v_.empty()) sift_down(0, last);
    }
    void replace_top(Key k) { sift_down(0, k); } // any key: the top has no parent
    // Replaces every key k by f(k), dropping those mapped to 0, and restores
    // the heap in O(n): cheaper than popping each changed key in turn.
    template <class F>
    void rebuild(F f) {
        std::size_t n = 0;
        for (Key k : v_)
            if (Key nk = f(k); nk != 0) v_[n++] = nk;
        v_.resize(n);
        for (std::size_t i = (v_.size() + 2) / 4; i-- > 0;) sift_down(i, v_[i]);
    }

private:
    void sift_down(std::size_t i, Key k) {
        const std::size_t n = v_.size();
        while (true) {
            std::size_t c = 4 * i + 1;
            if (c >= n) break;
            std::size_t best = c;
            const std::size_t end = std::min(c + 4, n);
            for (std::size_t j = c + 1; j < end; ++j)
                if (v_[j] > v_[best]) best = j;
            if (v_[best] <= k) break;
            v_[i] = v_[best];
            i = best;
        }
        v_[i] = k;
    }
    std::vector<Key> v_;
};

// Per-quad state of the replayed sequence: its cached bound, the step it was
// last exact at / band-bounded at, whether its pushed quad is valid, and
// whether its floor-sum bound was taken. One record, so a pop touches one
// cache line.
struct QuadState {
    std::int32_t bound; // < 2^31: areas of images with sides <= 16384
    std::int32_t fresh, banded;
    std::uint8_t valid, refined; // valid: unknown 0, no 1, yes 2
};

struct Sequence {
    std::vector<HalfPolygon> polygons;
    i64 covered = 0; // exact: texel squares inside the polygons
};

// Candidates kept at most; past this the search uses what it has (the
// budget of analyze.h). 12 bytes each.
constexpr std::size_t kMaxStoredQuads = std::size_t(1) << 22;

// The paper's own greedy sequence (paper_quad_search.cpp: the same quads,
// the same choices and stopping rules), computed cheaply: the guard that
// keeps the fast method from ever covering less than the paper.
class PaperReplay {
public:
    PaperReplay(const SafeGrid& grid, int min_area, SearchCounters& counters)
        : grid_(grid), counters_(counters), segments_(find_opaque_segments(grid.safe_mask, 3)), min_area_(min_area) {}

    Sequence run(const OpaqueOptions& options) {
        budget_base_ = counters_.work;
        enumerate();
        budget_base_ = counters_.work;
        return paper_sequence(options);
    }

private:
    // The paper's FindOpaqueQuadRecursive over every top in scan order, once:
    // the quads do not depend on the coverage map, only their counts do, so
    // every greedy step reuses them. Each (top, left, right, current) state is
    // expanded once; the paper re-walks every path reaching it, producing the
    // same quads again later, which never changes its first maximum.
    void enumerate() {
        seen_stamp_.assign(segments_.size(), -1);
        seen_.resize(segments_.size());
        for (int top = 0; top < int(segments_.size()) && !counters_.budget_exhausted; ++top)
            recurse(top, top, top, top);
    }

    bool first_visit(int top, int left, int right, int current) {
        if (seen_stamp_[current] != top) {
            seen_stamp_[current] = top;
            seen_[current].clear();
        }
        for (auto [l, r] : seen_[current])
            if (l == left && r == right) return false;
        seen_[current].push_back({left, right});
        return true;
    }

    void recurse(int top_i, int left_i, int right_i, int current_i) {
        for (int next_i : segments_[current_i].down) {
            if (over_budget() || quads_.size() >= kMaxStoredQuads) {
                counters_.budget_exhausted = true;
                return;
            }
            int new_left = left_i, new_right = right_i;
            PaperQuad q;
            if (!paper_step(segments_, top_i, current_i, next_i, new_left, new_right, q)) continue;
            if (!first_visit(top_i, new_left, new_right, next_i)) continue;
            ++counters_.candidates;
            ++counters_.work;
            // A quad whose count cannot reach min_area can never be chosen;
            // its branch may still hold larger ones.
            StoredQuad stored{std::int16_t(q.x0), std::int16_t(q.x1), std::int16_t(q.x2), std::int16_t(q.x3),
                              std::int16_t(q.y0), std::int16_t(q.y1)};
            if (paper_cheap_bound(stored) >= min_area_) quads_.push_back(stored);
            recurse(top_i, new_left, new_right, next_i);
        }
    }

    // True when no polygon placed at steps [since, placed.size()) touched a
    // texel the quad reads: then a bound or exact value it had at step
    // `since` still holds, and recomputing it would give the same number.
    // Saves most of the work after the first step on images whose polygons
    // are far apart.
    static bool untouched_since(int since, const StoredQuad& q, const std::vector<TexelBox>& placed) {
        if (since < 0) return false;
        const TexelBox b = q.box();
        for (std::size_t k = std::size_t(since); k < placed.size(); ++k)
            if (placed[k].meets(b)) return false;
        return true;
    }

    // Sets the bound of quad i, the heap's top; below `least` it can never
    // be accepted and leaves the heap.
    static void set_top_bound(KeyHeap& heap, QuadState& st, int i, i64 b, i64 least) {
        if (b == st.bound) return;
        st.bound = std::int32_t(b);
        if (b < least) heap.pop();
        else heap.replace_top(make_key(b, i));
    }

    // At the start of a step, after a large polygon: every quad whose box it
    // touched gets the uncovered texels of its box as a bound (O(1)), and the
    // heap is rebuilt once, instead of popping and re-pushing those quads one
    // by one (they are most of the heap on solid shapes).
    void rebound_all(KeyHeap& heap, std::vector<QuadState>& state, const BoxSums& in_box, const TexelBox& last,
                     i64 least) {
        // A small polygon touches few quads, which the lazy loop handles
        // for less than a pass over the whole heap (in random quad order).
        const i64 area = i64(last.x1 - last.x0) * (last.y1 - last.y0);
        if (8 * area < i64(grid_.width) * grid_.height) return;
        heap.rebuild([&](Key k) -> Key {
            const int i = key_index(k);
            const TexelBox b = quads_[i].box();
            if (!last.meets(b)) return k;
            QuadState& st = state[i];
            const i64 bound = std::min<i64>(st.bound, in_box.box(b.x0, b.y0, b.x1, b.y1));
            st.bound = std::int32_t(bound);
            return bound < least ? 0 : make_key(bound, i);
        });
        counters_.work += i64(state.size());
    }

    // Sets mask bits inside `box` (clamped to the grid) to value(index) and
    // updates the count of set bits and both prefix sums to match: a step
    // changes the mask only where its polygon lies.
    template <class F>
    void update_in(TexelBox box, Mask& mask, i64& set, RowSums& rows, BoxSums& boxes, F value) const {
        const int w = grid_.width;
        box.x0 = std::clamp(box.x0, 0, w), box.x1 = std::clamp(box.x1, 0, w);
        box.y0 = std::clamp(box.y0, 0, grid_.height), box.y1 = std::clamp(box.y1, 0, grid_.height);
        if (box.x1 <= box.x0 || box.y1 <= box.y0) return;
        for (int y = box.y0; y < box.y1; ++y)
            for (int x = box.x0; x < box.x1; ++x) {
                const std::size_t k = std::size_t(y) * w + std::size_t(x);
                const std::uint8_t v = value(k) ? 1 : 0;
                set += i64(v) - i64(mask.bits[k] != 0);
                mask.bits[k] = v;
            }
        rows.refresh_rows(mask, box.y0, box.y1);
        boxes.refresh_from(mask, box.y0);
    }

    // The per-quad states, shared by both sequences (one allocation).
    std::vector<QuadState>& reset_states() {
        states_.assign(quads_.size(), QuadState{0, -1, 0, 0, 0});
        return states_;
    }

    // The enumeration and each sequence get kFastOpaqueWorkBudget of their
    // own, so running out in ours still leaves the paper's replay its share.
    bool over_budget() {
        if (counters_.work - budget_base_ > kFastOpaqueWorkBudget) {
            counters_.budget_exhausted = true;
            return true;
        }
        return false;
    }


    // Counted texels in up to kBands horizontal bands of the integer quad,
    // each band as wide as the quad gets within it (its sides at the band's
    // ends, rounded outward): much tighter than the quad's box for sloped
    // sides. It bounds both the texel squares inside the quad and the
    // paper's row spans, which round the same sides to the nearest texel.
    // Applied lazily, only to quads that reach the top of the heap: at step
    // 0 nothing is covered yet and the first bounds are tighter.
    static constexpr int kBands = 8;
    // Work units of a heap pop with its bound updates (about the cost of
    // counting this many rows), so the budget bounds time on images with
    // millions of quads too.
    static constexpr i64 kPopWork = 32;
    static i64 band_bound(const StoredQuad& s, const BoxSums& counted) {
        static_assert(kBands == 8, "band ends are y0 + dy k / 8 by a shift");
        const int y0 = s.y0, dy = s.y1 - s.y0;
        // The sides at the band ends, through a reciprocal instead of a
        // division each: divisions were most of this bound's cost, and it
        // runs once per quad and step. The numerators stay below 2^30, so
        // n * (1 / dy) is within a few ulps of n / dy: it can only land on
        // the wrong side of an integer when n / dy is that integer, and then
        // the floor / ceiling below moves the side outward by one, which
        // keeps the bound a bound.
        const double inv = 1.0 / dy;
        int ys[kBands + 1], lefts[kBands + 1], rights[kBands + 1];
        const int bands = std::min(kBands, dy);
        for (int k = 0; k <= bands; ++k) {
            const int y = y0 + (dy >= kBands ? (dy * k) >> 3 : k);
            ys[k] = y;
            lefts[k] = int(std::floor(double(s.x0 * dy + (s.x3 - s.x0) * (y - y0)) * inv));
            rights[k] = int(std::ceil(double(s.x1 * dy + (s.x2 - s.x1) * (y - y0)) * inv));
        }
        i64 n = 0;
        for (int k = 0; k < bands; ++k)
            n += counted.box(std::min(lefts[k], lefts[k + 1]), ys[k], std::max(rights[k], rights[k + 1]), ys[k + 1]);
        return n;
    }

    i64 mark_covered(const HalfPolygon& p) {
        i64 newly = 0;
        for (int y = 0; y < grid_.height; ++y) {
            i64 lo, hi;
            covered_columns(p, y, lo, hi);
            for (i64 x = std::max<i64>(lo, 0); x < std::min<i64>(hi, grid_.width); ++x) {
                std::size_t i = std::size_t(y) * grid_.width + std::size_t(x);
                newly += covered_.bits[i] == 0 && grid_.safe_mask.bits[i];
                covered_.bits[i] = 1;
            }
        }
        return newly;
    }

    // ---- The paper's sequence (paper_quad_search.cpp), the same choices,
    // lazily like ours: its count only shrinks as the map fills, the first
    // bound is the exact sum of its span lengths (O(log)), and a count costs
    // O(rows) with row sums instead of O(area). Ties go to the earlier quad,
    // as the paper's first maximum does: the heap orders equal bounds by
    // index.

    Sequence paper_sequence(const OpaqueOptions& options) {
        Sequence seq;
        if (quads_.empty()) return seq; // it has nothing to choose from
        const int w = grid_.width;
        std::vector<std::int8_t> map(grid_.safe_mask.bits.begin(), grid_.safe_mask.bits.end());
        const i64 opaque = std::count(map.begin(), map.end(), 1);
        if (opaque == 0) return seq;
        i64 paper_covered = 0;
        covered_ = grid_.safe_mask;
        std::fill(covered_.bits.begin(), covered_.bits.end(), 0);
        // The texels the paper's map still counts (map > 0), with their
        // counts, updated where each step's quad lies instead of rebuilt.
        Mask positive = grid_.safe_mask;
        i64 positive_left = opaque;
        RowSums counts(positive);
        BoxSums in_box(positive);
        const std::size_t n = quads_.size();
        const i64 least = std::max(1, options.min_area); // a smaller count is never accepted
        std::vector<QuadState>& state = reset_states(); // valid: unknown (0), no (1), yes (2)
        std::vector<Key> keys;
        for (std::size_t i = 0; i < n; ++i) {
            state[i].bound = std::int32_t(paper_cheap_bound(quads_[i]));
            if (state[i].bound >= least) keys.push_back(make_key(state[i].bound, int(i)));
        }
        KeyHeap heap;
        heap.assign(std::move(keys));
        counters_.work += i64(n);
        std::vector<TexelBox> placed; // where each step changed the paper's map
        for (int step = 0; int(seq.polygons.size()) < options.max_polygons &&
                           double(paper_covered) / double(opaque) < options.min_coverage;
             ++step) {
            if (positive_left < least) break; // no count can reach it
            if (step > 0) rebound_all(heap, state, in_box, placed.back(), least);
            int winner = -1;
            while (!heap.empty() && !over_budget()) {
                const int i = key_index(heap.top());
                QuadState& st = state[i];
                counters_.work += kPopWork;
                if (st.fresh != step && untouched_since(st.fresh, quads_[i], placed)) st.fresh = step;
                if (st.fresh == step) {
                    // Its count is exact and nothing above it can beat it:
                    // only now is its pushed quad checked, once, since most
                    // counted quads fall behind another and never need it.
                    if (st.valid == 0) {
                        st.valid = trapezoid_valid(paper_pushed(quads_[i].quad()), grid_, counters_.work) ? 2 : 1;
                        if (st.valid == 1) {
                            heap.pop();
                            continue;
                        }
                    }
                    winner = i;
                    break;
                }
                auto lowered = [&](i64 b) {
                    if (b >= st.bound) return false;
                    set_top_bound(heap, st, i, b, least);
                    return heap.empty() || key_index(heap.top()) != i;
                };
                PaperQuad q = quads_[i].quad();
                if (!st.refined) {
                    st.refined = 1;
                    if (lowered(paper_span_total(q))) continue;
                }
                if (step > 0 && st.banded != step) {
                    const bool same = st.banded > 0 && untouched_since(st.banded, quads_[i], placed);
                    st.banded = step;
                    if (!same && lowered(band_bound(quads_[i], in_box))) continue;
                }
                const i64 count = paper_count(q, counts);
                counters_.work += q.y1 - q.y0;
                st.fresh = step;
                set_top_bound(heap, st, i, st.valid == 1 ? 0 : count, least);
            }
            if (winner < 0) break;
            PaperQuad best = quads_[winner].quad();
            placed.push_back(quads_[winner].box());
            for (int y = best.y0; y < best.y1; ++y) {
                int x0, x1;
                paper_row_span(best, y, w, x0, x1);
                for (int x = x0; x < x1; ++x) {
                    std::int8_t& m = map[std::size_t(y) * w + x];
                    paper_covered += m > 0;
                    if (m != 0) m = -1;
                }
            }
            update_in(placed.back(), positive, positive_left, counts, in_box,
                      [&](std::size_t k) { return map[k] > 0; });
            HalfPolygon poly = paper_pushed(best).polygon();
            seq.covered += mark_covered(poly);
            seq.polygons.push_back(std::move(poly));
        }
        return seq;
    }

    // CountCoveredPixels with row sums: paper_row_span for every row, its
    // rounded sides stepped without a division per row.
    i64 paper_count(const PaperQuad& q, const RowSums& counts) const {
        const i64 dy = q.y1 - q.y0, w = grid_.width;
        // round(d k / dy), half away from zero, is floor((2 d k + dy) / 2 dy)
        // for d >= 0 and its mirror for d < 0; both linear in k.
        const i64 dl = q.x3 - q.x0, dr = q.x2 - q.x1;
        FloorStepper left(2 * std::abs(dl), dy, 2 * dy), right(2 * std::abs(dr), dy, 2 * dy);
        i64 n = 0;
        for (int y = q.y0; y < q.y1; ++y, left.next(), right.next()) {
            const i64 l = q.x0 + (dl >= 0 ? left.value() : -left.value());
            const i64 r = q.x1 + (dr >= 0 ? right.value() : -right.value());
            n += counts.span(y, int(std::clamp<i64>(l, 0, w)), int(std::clamp<i64>(r, 0, w)));
        }
        return n;
    }

    // Sum of the paper's span lengths without the floor sums: each span is
    // at most its unrounded width plus one.
    static i64 paper_cheap_bound(const StoredQuad& q) {
        const i64 dy = q.y1 - q.y0, wt = q.x1 - q.x0, wb = q.x2 - q.x3;
        return floor_div(2 * dy * wt + (wb - wt) * (dy - 1), 2) + dy;
    }

    const SafeGrid& grid_;
    SearchCounters& counters_;
    std::vector<Segment> segments_;
    std::vector<StoredQuad> quads_; // the paper's candidates, in its order
    std::vector<QuadState> states_;
    std::vector<int> seen_stamp_;
    std::vector<std::vector<std::pair<int, int>>> seen_;
    Mask covered_;
    int min_area_;
    i64 budget_base_ = 0;
};

} // namespace

std::vector<HalfPolygon> replay_paper_polygons(const Mask& safe, const OpaqueOptions& options, SearchCounters& counters) {
    const SafeGrid grid(safe);
    return PaperReplay(grid, options.min_area, counters).run(options).polygons;
}

std::vector<HalfPolygon> fast_opaque_polygons(const Mask& safe, const OpaqueOptions& options, SearchCounters& counters) {
    const SafeGrid grid(safe);
    GrownPolygons grown = grow_opaque_polygons(grid, options, counters);
    // Ties go to the grown polygons: fewer vertices are not the point, but
    // the replay is only a guard. The grown polygons must match the paper's
    // in texel squares covered and in texel centres covered (the pixels the
    // opaque pass draws at 1:1; issue 25: by squares alone the grown ones
    // won on sprites where they drew under 0.9x of the paper's pixels).
    Sequence paper = PaperReplay(grid, options.min_area, counters).run(options);
    const bool grown_wins = grown.covered >= paper.covered &&
                            centre_covered_texels(grown.polygons) >= centre_covered_texels(paper.polygons);
    return grown_wins ? std::move(grown.polygons) : std::move(paper.polygons);
}

} // namespace depthcull::opaque_detail
