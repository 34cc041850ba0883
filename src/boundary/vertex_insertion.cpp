// Paper 2.1.2: vertex insertion.
//
// On edge AB (with neighbours C before A and D after B) a new vertex P is
// pulled inward along the edge's normal from the point of the edge farthest
// from the texels; A and B slide along lines CA and DB (toward C or D when
// reflex, away otherwise) until AP and PB are clear. Each position of P is
// a candidate.
//
// Departures from the paper, and why:
// - The farthest point is searched at up to kSamples points of the edge and
//   the inward march stops at the grid, not at the image border: a ray that
//   leaves the grid without meeting a texel only rules that sample out
//   (the paper gives up on the edge, to avoid separate parts; separate parts
//   are handled in parts.cpp, and accept_candidate keeps every texel in).
// - P, A and B are rounded to the grid (P to the nearest point: only the
//   candidate's acceptance matters; A and B outward of their lines).
// - Steps are coarsened on large sprites (at most ~kMaxSteps per search) so
//   the cost per image stays bounded.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "boundary/boundary_internal.h"

namespace depthcull::boundary {

namespace {

constexpr int kSamples = 64;
constexpr int kSearches = 3;      // farthest samples searched
constexpr int kVariantSteps = 8;  // slider steps allowed past the shared position
constexpr std::int64_t kMaxSteps = 256;

// Distance (in whole steps of the unit normal) from s to the first occupied
// cell, or 0 when the march leaves the grid first.
int inward_distance(const CellGrid& grid, double sx, double sy, double nx, double ny) {
    const int limit = grid.width() + grid.height();
    for (int t = 1; t <= limit; ++t) {
        double x = sx + t * nx, y = sy + t * ny;
        if (x < 0 || y < 0 || x >= grid.width() || y >= grid.height()) return 0;
        if (grid.occupied(std::int64_t(std::floor(x)), std::int64_t(std::floor(y)))) return t;
    }
    return 0;
}

// A vertex sliding along the line through `from` (the fixed neighbour) and
// `v`: toward `from` when reflex, away from it otherwise. Rounded outward of
// the directed polygon edge e0 -> e1 that runs along that line.
struct Slider {
    Pt v, dir, e0, e1;
    std::int64_t len = 1;     // major length of dir
    std::int64_t limit = -1;  // last k (toward the neighbour), -1: none
    std::int64_t k = 0;

    Pt at() const { return k == 0 ? v : round_outward(e0, e1, v, dir, k, len); }
};

Slider make_slider(Pt v, Pt neighbour, bool reflex, bool neighbour_before) {
    Slider s;
    s.v = v;
    Pt along = neighbour - v; // toward the neighbour
    s.dir = reflex ? along : Pt{-along.x, -along.y};
    s.len = std::max<std::int64_t>(1, std::max(std::llabs(along.x), std::llabs(along.y)));
    if (reflex) s.limit = s.len - 1; // the edge to the neighbour must keep a positive length
    s.e0 = neighbour_before ? neighbour : v;
    s.e1 = neighbour_before ? v : neighbour;
    return s;
}

// Slides until segment (slider, p) is clear; false when it runs out of its
// edge or its bounds first.
bool slide_until_clear(const CellGrid& grid, const Bounds& bounds, Slider& s, Pt p, std::int64_t step,
                       int max_steps) {
    for (int moves = 0; max_steps < 0 || moves <= max_steps; ++moves) {
        Pt v = s.at();
        if (!bounds.contains(v)) return false;
        if (grid.segment_clear(v, p)) return true;
        s.k += step;
        if (s.limit >= 0 && s.k > s.limit) return false;
    }
    return false;
}

} // namespace

void insert_boundary_vertex(const CellGrid& grid, const Bounds& bounds, const IPolygon& p, int i,
                            std::vector<Candidate>& out) {
    const int n = int(p.size());
    const int ia = i, ib = (i + 1) % n;
    const Pt c = p[std::size_t((i + n - 1) % n)], a = p[std::size_t(ia)], b = p[std::size_t(ib)],
             d = p[std::size_t((i + 2) % n)];
    const Pt e = b - a;
    const double len = std::hypot(double(e.x), double(e.y));
    if (len < 2) return;
    const double nx = -double(e.y) / len, ny = double(e.x) / len; // inward normal

    // The points of the edge farthest from the texels along the normal (the
    // paper takes the single farthest; a few more are cheap and often win).
    struct Sample {
        double x, y;
        int dist;
    };
    std::vector<Sample> samples;
    const int count = int(std::min<std::int64_t>(kSamples, std::max(std::llabs(e.x), std::llabs(e.y))));
    for (int k = 1; k < count; ++k) {
        double sx = a.x + double(e.x) * k / count, sy = a.y + double(e.y) * k / count;
        int dist = inward_distance(grid, sx, sy, nx, ny);
        if (dist >= 1) samples.push_back({sx, sy, dist});
    }
    std::stable_sort(samples.begin(), samples.end(), [](const Sample& l, const Sample& r) { return l.dist > r.dist; });
    if (samples.size() > std::size_t(kSearches)) samples.resize(std::size_t(kSearches));

    const std::int64_t step = std::max<std::int64_t>(1, std::max(grid.width(), grid.height()) / kMaxSteps);
    const std::int64_t old_area2 = twice_area(p);
    const Slider start_a = make_slider(a, c, orient(c, a, b) < 0, true);
    const Slider start_b = make_slider(b, d, orient(a, b, d) < 0, false);

    // The candidate with A, B replaced by a2, q, b2.
    auto offer = [&](Pt a2, Pt q, Pt b2) {
        IPolygon r;
        r.reserve(p.size() + 1);
        for (int k = 0; k < n; ++k) {
            if (k == ia) {
                r.push_back(a2);
                r.push_back(q);
            } else if (k == ib) {
                r.push_back(b2);
            } else {
                r.push_back(p[std::size_t(k)]);
            }
        }
        // The transparent corners this may leave at A or B (paper Figure
        // 2b) are removed after the insertion is accepted (boundary_polygon.cpp).
        std::int64_t area2 = twice_area(r);
        if (area2 < old_area2) out.push_back({std::move(r), area2});
    };

    for (const Sample& smp : samples) {
        Slider sa = start_a, sb = start_b;
        // Half steps, up to the texels themselves: the grid points around
        // the last position may still be clear (an inner corner).
        const int p_step = std::max(1, 2 * smp.dist / int(kMaxSteps / 4));
        for (int half = p_step; half <= 2 * smp.dist; half += p_step) {
            const double t = half / 2.0;
            const double px = smp.x + t * nx, py = smp.y + t * ny;
            const Pt nearest{std::llround(px), std::llround(py)};
            if (!bounds.contains(nearest)) break;
            Slider na = sa, nb = sb;
            const bool clear = slide_until_clear(grid, bounds, na, nearest, step, -1) &&
                               slide_until_clear(grid, bounds, nb, nearest, step, -1);
            if (clear) {
                sa = na, sb = nb;
                offer(sa.at(), nearest, sb.at());
            }
            // The other grid points around the exact position: the one that
            // lands on an inner corner of the texels is often among them.
            // Their sliders may go only a few steps past the shared ones.
            const std::int64_t fx = std::int64_t(std::floor(px)), fy = std::int64_t(std::floor(py));
            for (int k = 0; k < 4; ++k) {
                Pt q{fx + (k & 1), fy + (k >> 1)};
                if (q == nearest || !bounds.contains(q)) continue;
                Slider ta = sa, tb = sb;
                if (slide_until_clear(grid, bounds, ta, q, step, kVariantSteps) &&
                    slide_until_clear(grid, bounds, tb, q, step, kVariantSteps))
                    offer(ta.at(), q, tb.at());
            }
            if (!clear) break; // deeper positions only need longer slides
        }
    }
}

} // namespace depthcull::boundary
