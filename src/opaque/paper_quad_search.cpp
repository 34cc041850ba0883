// Paper 2.2: "Depth-Cull Optimization of 2D Scenes for 3D Graphics
// Hardware" (A. Church), GenerateOpaquePolygons / FindOpaqueQuad /
// FindOpaqueQuadRecursive / CountCoveredPixels / FillCoveredPixels, with the
// fixes of ERRATA.md. This is the reference the fast search is measured
// against, so it keeps the paper's costs: every candidate quad is counted by
// scanning its texels (O(w*h) each, 2.2.2).
//
// Departures, each because the prose asks for something the pseudocode does
// not deliver:
// - The chosen quad is checked exactly (trapezoid_valid) after the 0.5 push
//   of GenerateOpaquePolygons; the pseudocode's rounding does not guarantee
//   that no non-opaque texel is touched, which the prose requires ("no
//   non-opaque pixels"). An invalid quad is skipped for the next best one.
// - FillCoveredPixels marks only opaque texels, so OpaqueCoverage stays a
//   fraction of opaque texels.
// - A work budget (kPaperOpaqueWorkBudget) stops the exponential search
//   (2.2.2, section 4 caveat 3) and keeps the best quad found.
#include <algorithm>

#include "opaque/opaque_internal.h"

namespace depthcull::opaque_detail {

namespace {

// Paper CountCoveredPixels rounds dx/dy * y; half away from zero.
i64 round_div(i64 n, i64 d) { // d > 0
    return n >= 0 ? floor_div(2 * n + d, 2 * d) : -floor_div(-2 * n + d, 2 * d);
}

} // namespace

bool paper_step(const std::vector<Segment>& segments, int top_i, int current_i, int next_i, int& left_i, int& right_i,
                PaperQuad& q) {
    const Segment& top = segments[top_i];
    const Segment& next = segments[next_i];
    const i64 dy_next = next.y - top.y;
    if (current_i == top_i) { // errata: "this == top"
        left_i = right_i = next_i;
    } else {
        // Would the edges fall outside |next|? Round outward.
        const Segment& l = segments[left_i];
        const Segment& r = segments[right_i];
        i64 x_left = top.x0 + floor_div((l.x0 - top.x0) * dy_next, l.y - top.y);
        i64 x_right = top.x1 + ceil_div((r.x1 - top.x1) * dy_next, r.y - top.y);
        if (x_left < next.x0) left_i = next_i;
        if (x_right > next.x1) right_i = next_i;
    }
    // The vertices, rounding inward (errata: the garbled x_left line). The
    // limiting segments are never |top| here, so dy > 0.
    const Segment& l = segments[left_i];
    const Segment& r = segments[right_i];
    i64 x_left = top.x0 + ceil_div((l.x0 - top.x0) * dy_next, l.y - top.y);
    i64 x_right = top.x1 + floor_div((r.x1 - top.x1) * dy_next, r.y - top.y);
    // Note the +1 on the right: segment x1 is inclusive.
    q = {top.x0, top.x1 + 1, int(x_right) + 1, int(x_left), top.y, next.y + 1, 0};
    // Shift the X coordinate for obtuse angles 1 pixel inward.
    if (q.x0 > q.x3) ++q.x0;
    else if (q.x3 > q.x0) ++q.x3;
    if (q.x1 < q.x2) --q.x1;
    else if (q.x2 < q.x1) --q.x2;
    return q.x2 > q.x3;
}

Trapezoid paper_pushed(const PaperQuad& q) {
    // "Push the vertices in by 0.5 pixels on each axis so the edges don't
    // touch any non-opaque pixels when rasterized."
    return {2 * i64(q.y0) + 1, 2 * i64(q.y1) - 1, 2 * i64(q.x0) + 1, 2 * i64(q.x1) - 1,
            2 * i64(q.x3) + 1, 2 * i64(q.x2) - 1};
}

void paper_row_span(const PaperQuad& q, int y, int width, int& x0, int& x1) {
    const i64 dy = q.y1 - q.y0;
    i64 left = q.x0 + round_div(i64(q.x3 - q.x0) * (y - q.y0), dy);
    i64 right = q.x1 + round_div(i64(q.x2 - q.x1) * (y - q.y0), dy);
    x0 = int(std::clamp<i64>(left, 0, width));
    x1 = int(std::clamp<i64>(right, 0, width));
}

namespace {

class PaperSearch {
public:
    PaperSearch(const Mask& safe, SearchCounters& counters)
        : safe_(safe), grid_(safe), counters_(counters), segments_(find_opaque_segments(safe, 3)) {
        // Map opaque texels to 1, all others to 0 (GenerateOpaquePolygons).
        map_.assign(safe.bits.begin(), safe.bits.end());
    }

    std::vector<HalfPolygon> run(const OpaqueOptions& options) {
        std::vector<HalfPolygon> polygons;
        const i64 opaque = std::count(map_.begin(), map_.end(), 1);
        if (opaque == 0) return polygons;
        i64 covered = 0;
        while (int(polygons.size()) < options.max_polygons &&
               double(covered) / double(opaque) < options.min_coverage && !counters_.budget_exhausted) {
            PaperQuad best = find_opaque_quad();
            if (best.count == 0 || best.count < options.min_area) break;
            covered += fill_covered_pixels(best);
            polygons.push_back(paper_pushed(best).polygon());
        }
        return polygons;
    }

private:
    // FindOpaqueQuad: max(candidates), skipping quads the exact check
    // rejects (see top); among equal counts the first found wins. Keeping
    // only the running best is the same choice as collecting every
    // candidate, without the memory.
    PaperQuad find_opaque_quad() {
        best_ = {};
        for (std::size_t s = 0; s < segments_.size() && !counters_.budget_exhausted; ++s)
            recurse(int(s), int(s), int(s), int(s));
        return best_;
    }

    // FindOpaqueQuadRecursive(top, left, right, current). Recursion depth is
    // at most the image height (one level per row).
    void recurse(int top_i, int left_i, int right_i, int current_i) {
        for (int next_i : segments_[current_i].down) {
            if (counters_.work > kPaperOpaqueWorkBudget) {
                counters_.budget_exhausted = true;
                return;
            }
            int new_left = left_i, new_right = right_i;
            PaperQuad q;
            if (!paper_step(segments_, top_i, current_i, next_i, new_left, new_right, q)) continue;
            q.count = count_covered_pixels(q);
            ++counters_.candidates;
            if (q.count > best_.count && trapezoid_valid(paper_pushed(q), grid_, counters_.work)) best_ = q;
            recurse(top_i, new_left, new_right, next_i);
        }
    }

    template <class F>
    void for_each_row_span(const PaperQuad& q, F&& f) const {
        for (int y = q.y0; y < q.y1; ++y) {
            int x0, x1;
            paper_row_span(q, y, safe_.width, x0, x1);
            f(y, x0, x1);
        }
    }

    i64 count_covered_pixels(const PaperQuad& q) {
        i64 n = 0;
        for_each_row_span(q, [&](int y, int x0, int x1) {
            const std::int8_t* row = &map_[std::size_t(y) * safe_.width];
            for (int x = x0; x < x1; ++x) n += row[x] > 0;
            counters_.work += std::max(1, x1 - x0);
        });
        return n;
    }

    i64 fill_covered_pixels(const PaperQuad& q) {
        i64 newly = 0;
        for_each_row_span(q, [&](int y, int x0, int x1) {
            std::int8_t* row = &map_[std::size_t(y) * safe_.width];
            for (int x = x0; x < x1; ++x)
                if (row[x] != 0) {
                    newly += row[x] > 0;
                    row[x] = -1;
                }
        });
        return newly;
    }

    const Mask& safe_;
    SafeGrid grid_;
    SearchCounters& counters_;
    std::vector<Segment> segments_;
    std::vector<std::int8_t> map_; // paper's coverage map: 0, +1, -1
    PaperQuad best_;               // of the current FindOpaqueQuad
};

} // namespace

std::vector<HalfPolygon> paper_opaque_polygons(const Mask& safe, const OpaqueOptions& options, SearchCounters& counters) {
    return PaperSearch(safe, counters).run(options);
}

} // namespace depthcull::opaque_detail
