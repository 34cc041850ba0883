// Issue 25, point 4: opaque merging (ReconstructOptions::merge_opaque).
//
// Whole-rect opaque tiles (Shape::rect in the opaque pass) that sit side by
// side on screen exactly as their rects sit side by side in the image (a
// building, a backdrop cut into tiles) have one texel map: the screen
// position of a texel is the same whichever of them draws it. Such tiles of
// one mesh key and colour are drawn as one quad: the union of their rects
// (rows of equal height first, then runs of equal columns stacked), drawn
// by the tile of the highest depth level L among them, at its depth, the
// others drawing nothing in the opaque pass. Every pixel shows the texel it
// showed; the frame loses triangles and edges (each shared tile edge is a
// run of 4x4 blocks llvmpipe shades twice).
//
// The depth band. Touching tiles overlap in the element graph, so
// neighbours have different levels. A tile of level l now drawn at L would
// win against what lies between, so a block is merged only when no other
// element of a level in (lowest, L] comes near it (screen boxes, touching
// counts, except for elements GL snaps exactly: their box is exact, and one
// that only touches the block's edge shares no pixel centre with it under
// the fill rule). Then any X outside the block drawn over a tile T of it (level X
// > level T >= lowest) has level X > L and still wins. Two blocks check
// each other the same way, so their new depths keep every overlap's order.
//
// Only with a plain renderer: a renderer that tests each element's rect
// (Draw::element_spans) would cut the quad at the first tile's rect.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <tuple>

#include "scene/internal.h"
#include "scene/placement.h"

namespace depthcull::detail {

namespace {

// Screen boxes of the elements that draw, in a uniform grid, for the depth
// band check; at most kMergeCheckBudget box tests in all (past it, no more
// blocks are merged: drawing tiles apart is always correct).
constexpr std::int64_t kMergeCheckBudget = std::int64_t(1) << 24;
constexpr double kCell = 64;          // px
constexpr double kNear = 1.0 / 32;    // px: boxes this close count as touching (kSeparation and rounding)

struct BoxGrid {
    std::vector<Box> box;             // per element
    std::vector<std::uint8_t> exact;  // per element: snaps exactly, so its box is exact
    std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::uint32_t>> cells;
    std::vector<std::uint32_t> big;   // spanning more than 16x16 cells: checked against every block
    std::int64_t budget = kMergeCheckBudget;

    BoxGrid(const Scene& scene, const ElementShapes& shapes) : box(scene.elements.size()), exact(scene.elements.size(), 0) {
        for (std::uint32_t i = 0; i < scene.elements.size(); ++i) {
            if (shapes.boundary[i] == Shape::none && shapes.opaque[i] == Shape::none) continue;
            const Element& e = scene.elements[i];
            Box b{INFINITY, INFINITY, -INFINITY, -INFINITY};
            for (Vec2 c : {Vec2{0, 0}, Vec2{double(e.rect.w), 0}, Vec2{0, double(e.rect.h)}, Vec2{double(e.rect.w), double(e.rect.h)}}) {
                const Vec2 s = apply(e.transform, c);
                b.x0 = std::min(b.x0, s.x), b.y0 = std::min(b.y0, s.y), b.x1 = std::max(b.x1, s.x), b.y1 = std::max(b.y1, s.y);
            }
            const bool finite = std::isfinite(b.x0) && std::isfinite(b.x1) && std::isfinite(b.y0) && std::isfinite(b.y1);
            if (!finite) b = {-INFINITY, -INFINITY, INFINITY, INFINITY}; // unknown reach: always in the way
            box[i] = b;
            exact[i] = finite && snaps_exactly(e.transform);
            const std::int64_t cx0 = cell(b.x0), cx1 = cell(b.x1), cy0 = cell(b.y0), cy1 = cell(b.y1);
            if (!finite || cx1 - cx0 > 16 || cy1 - cy0 > 16) {
                big.push_back(i);
                continue;
            }
            for (std::int64_t y = cy0; y <= cy1; ++y)
                for (std::int64_t x = cx0; x <= cx1; ++x) cells[{x, y}].push_back(i);
        }
    }
    static std::int64_t cell(double v) { return std::int64_t(std::floor(std::clamp(v, -1e15, 1e15) / kCell)); }
    static bool near(const Box& a, const Box& b) {
        return a.x0 <= b.x1 + kNear && b.x0 <= a.x1 + kNear && a.y0 <= b.y1 + kNear && b.y0 <= a.y1 + kNear;
    }
    // True when some element outside `member` of level in (lo, hi] comes near `b`; also when out of budget.
    bool blocked(const Box& b, std::int64_t lo, std::int64_t hi, const std::vector<std::int64_t>& levels,
                 const std::vector<std::uint8_t>& member) {
        auto test = [&](std::uint32_t x) {
            --budget;
            if (member[x] || levels[x] <= lo || levels[x] > hi) return false;
            const Box& a = box[x];
            return exact[x] ? a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1 : near(a, b);
        };
        for (std::uint32_t x : big)
            if (test(x)) return true;
        const std::int64_t cx0 = cell(b.x0 - kNear), cx1 = cell(b.x1 + kNear), cy0 = cell(b.y0 - kNear), cy1 = cell(b.y1 + kNear);
        if ((cx1 - cx0 + 1) * (cy1 - cy0 + 1) > budget) return true;
        for (std::int64_t y = cy0; y <= cy1; ++y)
            for (std::int64_t x = cx0; x <= cx1; ++x) {
                auto it = cells.find({x, y});
                if (it == cells.end()) continue;
                for (std::uint32_t k : it->second)
                    if (test(k)) return true;
            }
        return budget < 0;
    }
};

} // namespace

MergedTiles merge_opaque_tiles(const Scene& scene, const ElementShapes& shapes, const std::vector<std::int64_t>& levels,
                               const std::vector<std::int32_t>& keys, const ClippedParts* clipped) {
    MergedTiles out;
    const std::size_t n = scene.elements.size();
    out.absorbed.assign(n, 0);
    std::unique_ptr<BoxGrid> grid; // made when a block is found
    std::vector<std::uint8_t> member(n, 0);
    // Group: everything a vertex of the quad carries must agree.
    using Group = std::tuple<std::int32_t, std::array<double, 6>, std::array<float, 4>, int>;
    std::map<Group, std::vector<std::uint32_t>> groups;
    for (std::uint32_t i = 0; i < n; ++i) {
        const Element& e = scene.elements[i];
        if (shapes.opaque[i] != Shape::rect || shapes.blended[i] || keys[i] < 0 || e.animation >= 0) continue;
        if (clipped && clipped->opaque.count(i)) continue;
        const auto& m = e.transform;
        // Axis-aligned and snapped exactly: the union's corners land where the tiles' corners do.
        if (m[1] != 0 || m[2] != 0 || !snaps_exactly(m)) continue;
        const TexelMap t = texel_map(e);
        groups[Group{keys[i], {t.u0, t.ux, t.uy, t.v0, t.vx, t.vy}, e.color, int(e.blend)}].push_back(i);
    }
    for (auto& [group, members] : groups) {
        if (members.size() < 2) continue;
        // Rows: tiles of equal y and height whose rects continue each other in x.
        auto rect = [&](std::uint32_t i) { return scene.elements[i].rect; };
        std::sort(members.begin(), members.end(), [&](std::uint32_t a, std::uint32_t b) {
            const Rect ra = rect(a), rb = rect(b);
            return std::tie(ra.y, ra.h, ra.x, a) < std::tie(rb.y, rb.h, rb.x, b);
        });
        struct Run {
            std::uint32_t leader;
            std::vector<std::uint32_t> tiles;
            int x, y, w, h;
        };
        std::vector<Run> runs;
        for (std::uint32_t i : members) {
            const Rect r = rect(i);
            if (!runs.empty()) {
                Run& last = runs.back();
                if (last.y == r.y && last.h == r.h && last.x + last.w == r.x) {
                    last.w += r.w;
                    last.tiles.push_back(i);
                    continue;
                }
            }
            runs.push_back({i, {i}, r.x, r.y, r.w, r.h});
        }
        // Columns: runs of equal x and width stacked in y.
        std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) {
            return std::tie(a.x, a.w, a.y, a.leader) < std::tie(b.x, b.w, b.y, b.leader);
        });
        std::vector<Run> blocks;
        for (Run& r : runs) {
            if (!blocks.empty()) {
                Run& last = blocks.back();
                if (last.x == r.x && last.w == r.w && last.y + last.h == r.y) {
                    last.h += r.h;
                    last.tiles.insert(last.tiles.end(), r.tiles.begin(), r.tiles.end());
                    continue;
                }
            }
            blocks.push_back(std::move(r));
        }
        for (const Run& b : blocks) {
            if (b.tiles.size() < 2) continue;
            if (!grid) grid = std::make_unique<BoxGrid>(scene, shapes);
            std::uint32_t leader = b.tiles.front();
            std::int64_t lowest = levels[leader];
            Box box{INFINITY, INFINITY, -INFINITY, -INFINITY};
            for (std::uint32_t t : b.tiles) {
                if (levels[t] > levels[leader] || (levels[t] == levels[leader] && t < leader)) leader = t;
                lowest = std::min(lowest, levels[t]);
                const Box& tb = grid->box[t];
                box = {std::min(box.x0, tb.x0), std::min(box.y0, tb.y0), std::max(box.x1, tb.x1), std::max(box.y1, tb.y1)};
                member[t] = 1;
            }
            const bool blocked = grid->blocked(box, lowest, levels[leader], levels, member);
            for (std::uint32_t t : b.tiles) member[t] = 0;
            if (blocked) continue;
            for (std::uint32_t t : b.tiles) out.absorbed[t] = t != leader;
            out.quads.emplace(leader, rect_polygon(Rect{b.x, b.y, b.w, b.h}));
            out.blocks.emplace(leader, b.tiles);
            out.merged += std::int64_t(b.tiles.size());
        }
    }
    return out;
}

} // namespace depthcull::detail
