// Issue 25: frames without a depth buffer (ReconstructOptions::depthless).
//
// On llvmpipe a frame that clears and tests depth pays for it on every
// pixel, whether or not the test rejects anything (docs/ideal-frame.md
// section 10 measured it). The depth test is there so the opaque pass can
// go front to back and the blend pass can leave out what opaque polygons
// in front hide. Without it the same meshes draw the same frame when:
// - the opaque pass goes back to front: where opaque polygons overlap, the
//   nearest is written last (the blend pass's sorted order keeps every
//   element behind the ones it overlaps, and a subsequence of it does too);
// - no blend-pass polygon lies behind an opaque polygon of an element in
//   front (the blend pass comes after the opaque pass and would blend over
//   it). An element whose opaque polygons are in front of another's
//   blend-pass polygons draws them in the blend pass instead, in its place
//   in the order: its texels there are opaque and its colour's alpha is 1
//   (else it has no opaque polygons; a Blend::opaque element draws without
//   blending in either pass), so blending writes what the opaque pass
//   would, and what it hides (dropped, cut away, or drawn before it) stays
//   hidden. Screen boxes decide it: what f draws opaque against the rect
//   of each element behind it (everything an element draws lies in its
//   rect), from the element graph's edges, which cover every overlapping
//   pair except in crowded cells (ElementGraph::chained), where f moves.
// An element's own blend-pass polygons over its own opaque polygons blend
// its opaque texels over themselves, which changes nothing (with depth they
// were rejected at equal depth).
//
// Hidden parts cut away (clip_hidden_parts) leave a rim 1/16 px inside an
// occluder that the depth test used to reject: behind an opaque-pass
// polygon that rim is a blend-pass polygon of the element behind, so the
// occluder moves to the blend pass, which then draws over the rim.
#include <algorithm>
#include <cmath>

#include "scene/internal.h"
#include "scene/placement.h"

namespace depthcull::detail {

namespace {

struct Box {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    void add(Vec2 p) {
        x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
        x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
    }
    bool empty() const { return !(x0 <= x1 && y0 <= y1); }
};

Box screen_box(const Element& e, const std::vector<Polygon>& texel) {
    Box b;
    for (const Polygon& p : texel)
        for (const Vec2& v : p) b.add(apply(e.transform, {v.x - e.rect.x, v.y - e.rect.y}));
    return b;
}

// Beyond GL's snapping (1/512 px per coordinate), with room to spare; the
// vertices' float rounding grows with their coordinates (2^-24 relative,
// twice over for both boxes, and again for room).
constexpr double kApart = 1.0 / 32;
constexpr double kFloatRounding = 1.0 / 4194304; // 2^-22
// Whole-pixel coordinates stay exact as floats below 2^23.
constexpr double kExactFloat = 8388608;

double largest(const Box& b) { return std::max({std::abs(b.x0), std::abs(b.y0), std::abs(b.x1), std::abs(b.y1)}); }

// True when the two boxes can share no pixel centre: apart by more than
// snapping and rounding can move them, or, when both elements lie on whole
// pixels along the axes (their edges on whole-pixel lines, where no pixel
// centre lies, exact as floats), meeting at most along an edge.
bool disjoint(const Box& a, const Box& b, bool on_whole_pixels) {
    const double far = std::max(largest(a), largest(b));
    if (!(far < INFINITY)) return false;
    const double gap = on_whole_pixels && far < kExactFloat ? 0.0 : kApart + far * kFloatRounding;
    return a.x1 + gap <= b.x0 || b.x1 + gap <= a.x0 || a.y1 + gap <= b.y0 || b.y1 + gap <= a.y0;
}

} // namespace

std::vector<std::uint8_t> opaque_in_blend_pass(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                                               const ElementShapes& shapes, const ElementGraph& graph, const MeshBuilder& builder) {
    const std::size_t n = scene.elements.size();
    std::vector<std::uint8_t> moved(n, 0);
    std::vector<Box> rect_box(n);
    std::vector<std::uint8_t> aligned(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const Element& e = scene.elements[i];
        // Everything an element draws lies in its rect (texel skirts and
        // cut pieces are clamped to it).
        rect_box[i] = screen_box(e, {rect_polygon(e.rect)});
        aligned[i] = scene.filter == Filter::nearest && pixel_aligned(scene, e);
    }
    for (std::size_t f = 0; f < n; ++f) {
        if (shapes.opaque[f] == Shape::none) continue;
        // In a crowded cell the graph chained the elements instead of
        // comparing them: what f overlaps is not all among its edges.
        if (graph.is_chained(f)) {
            moved[f] = 1;
            continue;
        }
        const Element& e = scene.elements[f];
        // What f's opaque pass draws, as drawn (pulled in; out to the rect's
        // sides where it lies on whole pixels).
        Box opaque_box;
        if (shapes.opaque[f] == Shape::rect || !analyses[f]) {
            opaque_box = rect_box[f];
        } else {
            std::vector<Polygon> drawn;
            for (const Polygon& p : analyses[f]->opaque) drawn.push_back(builder.pull_inward(std::uint32_t(f), p));
            opaque_box = screen_box(e, drawn);
        }
        if (opaque_box.empty()) continue;
        for (const std::uint32_t* b = graph.behind_begin(f); b != graph.behind_end(f); ++b) {
            // Elements behind are earlier in painter's order and decided
            // already: one whose opaque polygons moved draws them blended.
            if (!shapes.blended[*b] && !moved[*b]) continue;
            if (disjoint(opaque_box, rect_box[*b], aligned[f] && aligned[*b])) continue;
            moved[f] = 1;
            break;
        }
    }
    return moved;
}

void keep_merged_in_order(const ElementGraph& graph, const std::vector<std::uint32_t>& order, const std::vector<std::uint8_t>& moved,
                          MergedTiles& merged) {
    if (merged.quads.empty()) return;
    const std::size_t n = graph.size();
    constexpr std::uint32_t kNone = 0xffffffffu;
    std::vector<std::int64_t> pos(n, -1);
    for (std::size_t k = 0; k < order.size(); ++k) pos[order[k]] = std::int64_t(k);
    std::vector<std::uint32_t> leader_of(n, kNone); // per tile of a block, its leader
    for (const auto& [leader, tiles] : merged.blocks)
        for (std::uint32_t t : tiles) leader_of[t] = leader;
    std::vector<std::uint8_t> broken(n, 0); // per leader
    for (std::size_t t = 0; t < n; ++t)
        if (leader_of[t] != kNone && (graph.is_chained(t) || moved[t] || pos[leader_of[t]] < 0)) broken[leader_of[t]] = 1;
    // One pass over the edges (j in front of b): an element in front of a
    // tile must come after the tile's leader, one behind a tile before it.
    for (std::size_t j = 0; j < n; ++j)
        for (const std::uint32_t* b = graph.behind_begin(j); b != graph.behind_end(j); ++b) {
            const std::uint32_t back = leader_of[*b], front = leader_of[j];
            if (back == front) continue; // one block, or neither in a block
            if (back != kNone && pos[j] <= pos[back]) broken[back] = 1;
            if (front != kNone && pos[*b] >= pos[front]) broken[front] = 1;
        }
    // Each block is decided alone, so the map's order does not matter.
    for (const auto& [leader, tiles] : merged.blocks) {
        if (!broken[leader]) continue;
        for (std::uint32_t t : tiles) merged.absorbed[t] = 0;
        merged.quads.erase(leader);
        merged.merged -= std::int64_t(tiles.size());
    }
}

void append_depthless_draws(const Scene& scene, const std::vector<std::uint32_t>& order, const std::vector<std::int64_t>& levels,
                            std::int64_t denominator, const ElementShapes& shapes, const std::vector<const ImageAnalysis*>& analyses,
                            const std::vector<std::int32_t>& keys, const std::vector<std::uint8_t>& moved, MeshBuilder& builder,
                            std::vector<Draw>& draws) {
    const std::vector<int> canon = canonical_images(scene);
    for (int pass = 0; pass < 2; ++pass) {
        std::int32_t last = -1;
        for (std::uint32_t e : order) {
            const bool opaque = shapes.opaque[e] != Shape::none && keys[e] >= 0;
            const bool in_pass = pass == 0 ? opaque && !moved[e] : shapes.blended[e] || (opaque && moved[e]);
            if (!in_pass) continue;
            const Element& el = scene.elements[e];
            if (keys[e] != last) {
                Draw d;
                d.image = canon[std::size_t(el.image)];
                d.pass = pass == 0 ? Pass::opaque : Pass::blend;
                d.blend = el.blend;
                draws.push_back(std::move(d));
                last = keys[e];
            }
            const ImageAnalysis* a = e < analyses.size() ? analyses[e] : nullptr;
            // The depth values of the plan with a depth buffer: drawn with
            // one anyway (an engine that keeps its depth test on), the
            // meshes draw the same frame.
            const float z = depth_z(levels[e], pass == 0, denominator);
            if (pass == 0) {
                builder.add_opaque(draws.back(), e, shapes.opaque[e], a, z);
                continue;
            }
            // A moved element's blend-pass polygons hold its opaque
            // polygons unless they were cut away there.
            if (opaque && moved[e] && (!shapes.blended[e] || builder.blend_cut(e))) builder.add_opaque(draws.back(), e, shapes.opaque[e], a, z);
            if (shapes.blended[e]) builder.add_boundary(draws.back(), e, shapes.boundary[e], a, z);
        }
    }
}

} // namespace depthcull::detail
