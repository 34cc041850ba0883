// Internal to src/scene: what each element draws, shared by the element
// graph, sorting and mesh generation.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "depthcull/scene.h"

namespace depthcull::detail {

// Where an element's polygons come from (texel space of its image).
enum class Shape : std::uint8_t {
    none,     // draws nothing (fully transparent rect): dropped
    analysis, // the per-image analysis polygons (paper 2.1 / 2.2)
    rect,     // the whole rect, one quad
};

struct ElementShapes {
    std::vector<Shape> boundary; // per element: blend pass polygons (and graph overlap)
    std::vector<Shape> opaque;   // per element: opaque pass polygons
    // Per element: whether it has a blend-pass draw. Blend "opaque"
    // elements with an opaque pass draw only there.
    std::vector<std::uint8_t> blended;
};

bool element_is_valid(const Scene& scene, const Element& e);

// Decides each element's shapes: see the rules in shapes.cpp. rect_edges:
// the meshes are for a plain renderer with texel skirts (texel_margin > 0,
// no coverage skirts), where some elements must draw overpaint's rect
// edges (needs_rect_edges in shapes.cpp).
ElementShapes element_shapes(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses, bool opaque_pass,
                             bool rect_edges = false);
// With rect_edges: whether an element whose analysis boundary lies within
// its rect draws its whole rect in the blend pass instead (the rule and its
// reason in shapes.cpp). bleeding_edges: ImageAnalysis::bleeding_edges.
bool needs_rect_edges(bool bleeding_edges, const std::array<double, 6>& transform);

// Marks elements whose rect lies entirely outside the viewport (by more
// than a pixel, for float rounding) as drawing nothing.
void cull_to_viewport(const Scene& scene, ElementShapes& shapes);

// The whole rect as a clockwise (y down) quad in texel space of the image.
Polygon rect_polygon(const Rect& r);

// Mesh keys: elements with equal keys can share a draw (CanShareMesh).
// Image entries with the same path share a texture, so the key uses the
// first image index with that path. Returns key per element.
std::vector<std::int32_t> mesh_keys(const Scene& scene);
// First image index with the same path as image i.
std::vector<int> canonical_images(const Scene& scene);

// The blend-pass order over elements whose key >= 0; elements with key < 0
// take no part (their edges are ignored: they draw nothing in this pass,
// so their order relative to others cannot change a blended pixel).
std::vector<std::uint32_t> sort_order(const ElementGraph& graph, const std::vector<std::int32_t>& keys, SortMethod method);
std::int64_t count_runs(const std::vector<std::uint32_t>& order, const std::vector<std::int32_t>& keys);

// `sorted` (null: all) marks the elements the blend-pass sort sees, so the
// chain that bounds the graph (element_graph.cpp) also links those directly.
ElementGraph build_graph(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                         const std::vector<Shape>& shapes, GraphMode mode, const std::vector<std::uint8_t>* sorted,
                         std::uint64_t pair_budget);

// build_graph through `memo` (null: built afresh): a build from the same
// shapes, boundary polygons (compared by value), mode and budget, and the
// same `sorted` where the graph chains, is the memo's graph again.
ElementGraph build_graph(GraphMemo* memo, const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                         const std::vector<Shape>& shapes, GraphMode mode, const std::vector<std::uint8_t>* sorted,
                         std::uint64_t pair_budget);
// ReconstructOptions::graph_memo: made here, kept by the caller for the
// frames of one scene, one reconstruction at a time.
struct GraphMemoDelete {
    void operator()(GraphMemo* memo) const;
};
std::unique_ptr<GraphMemo, GraphMemoDelete> make_graph_memo();
// How many builds `memo` answered (tests).
std::int64_t graph_memo_reused(const GraphMemo& memo);

} // namespace depthcull::detail

#include <unordered_map>

namespace depthcull::detail {

// Polygons captured in texel space instead of drawn (MeshBuilder::capture):
// the templates a FrameAssembler transforms per sprite.
struct TexelMesh {
    std::vector<Vec2> points; // texel positions in the image
    std::vector<std::uint32_t> indices;
};

// Issue 25 (clip_hidden.cpp): what an element draws instead of its
// polygons once the parts hidden behind opaque polygons in front are cut
// away: pieces in texel space of its image, each with its triangles.
struct ClippedPart {
    std::vector<Polygon> pieces;
    std::vector<std::vector<std::uint32_t>> triangles;
};
// The convex polygon p (either orientation) with edge k's line (from p[k])
// moved inward by d[k]; empty when an edge would flip or vanish
// (texel_margin.cpp).
Polygon move_edges_inward(const Polygon& p, const std::vector<double>& d);

// A point of Clipper's integer grid (clip_hidden.cpp: 2^-32 screen px).
struct GridPoint {
    std::int64_t x, y;
};
// Most points triangulate_with_holes takes (its tests grow as n^3).
constexpr std::size_t kMaxHoleTriangulationVertices = 64;
// The region inside contours[0] and outside contours[1..] (strictly simple,
// disjoint, the holes inside the first, no point twice, |coordinates| <
// 2^60) triangulated with short edges (greedy: shortest diagonals
// first); indices into the contours' points in order, triangles turning
// as contours[0]. Empty when the input breaks those rules or has more
// than kMaxHoleTriangulationVertices points: every triangle lies in the
// region and their areas sum to its area exactly, or none is returned.
// A diagonal passing closer than `clearance` (grid units), or than its
// length / max_aspect, to a point other than its ends is not taken: the
// thin triangle it would close could turn over once GL rounds the points,
// or sample texels loosely (clip_hidden.cpp). 0: no such limit.
// `cones` false: no diagonal is skipped for starting outside the region
// at an end (tests: the skip changes nothing but the time).
std::vector<std::uint32_t> triangulate_with_holes(const std::vector<std::vector<GridPoint>>& contours, std::int64_t clearance = 0,
                                                  double max_aspect = 0, bool cones = true);

struct ClippedParts {
    std::unordered_map<std::uint32_t, ClippedPart> blend;  // blend-pass polygons (or rect) cut
    std::unordered_map<std::uint32_t, ClippedPart> opaque; // whole-rect opaque tiles cut
    std::int64_t elements = 0;
};

// Issue 25 (opaque_merge.cpp): whole-rect opaque tiles drawn as one quad.
struct MergedTiles {
    std::unordered_map<std::uint32_t, Polygon> quads; // leader -> the union of its block's rects (texel space)
    std::vector<std::uint8_t> absorbed;               // per element: drawn by its block's leader
    std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> blocks; // leader -> its block's tiles (itself included)
    std::int64_t merged = 0;                          // tiles in blocks of two or more
};

// Appends elements' polygons to draws (paper 2.3.3 AddPolygon), caching
// the triangulation of each analysis polygon: elements sharing an image
// rect share the texel-space triangulation, and an affine transform keeps
// it valid. `element` indexes scene.elements; with element_spans its
// vertices are named first_map + element (Draw::element_spans).
class MeshBuilder {
public:
    explicit MeshBuilder(const Scene& scene, std::uint32_t first_map = 0, double coverage_margin = 0,
                         double texel_margin = kTexelMargin, bool element_spans = false)
        : scene_(scene), first_map_(first_map), margin_(coverage_margin), texel_margin_(texel_margin), spans_(element_spans) {}
    // Called before `element` appends vertices to d: starts a span when asked for.
    void note_element(Draw& d, std::uint32_t element) const {
        if (!spans_) return;
        const std::uint32_t id = first_map_ + element;
        if (d.element_spans.empty() || d.element_spans.back().element != id)
            d.element_spans.push_back({id, std::uint32_t(d.vertex_count())});
    }
    void add_boundary(Draw& d, std::uint32_t element, Shape shape, const ImageAnalysis* a, float z);
    // From now on polygons go to `mesh` (texel space) instead of a Draw;
    // always_skirt: texel skirts even where the element's transform snaps
    // exactly (a template serves every transform).
    // joined: texel skirts in the joined form (texel_margin.cpp), whose
    // pieces share vertices once welded.
    void capture(TexelMesh* mesh, bool always_skirt, bool joined = false) {
        capture_ = mesh;
        always_skirt_ = always_skirt;
        joined_ = joined;
    }
    // Per polygon of the last add_texel_skirts in the joined form: 1 where
    // the skirt is the polygon dilated (it holds the polygon itself).
    const std::vector<std::uint8_t>& dilated() const { return dilated_; }
    void add_opaque(Draw& d, std::uint32_t element, Shape shape, const ImageAnalysis* a, float z);
    // Elements named here draw their cut pieces instead (clip_hidden_parts).
    void set_clipped(const ClippedParts* clipped) { clipped_ = clipped; }
    // Whether clip_hidden_parts cut the element's blend-pass polygons.
    bool blend_cut(std::uint32_t element) const { return clipped_ && clipped_->blend.count(element) > 0; }
    // Tiles named here draw their block's quad, or nothing (merge_opaque_tiles).
    void set_merged(const MergedTiles* merged) { merged_ = merged; }

    // ReconstructOptions::coverage_margin: a skirt around `polygons` (of
    // `element`, texel space) when the margin is positive. Returns, per
    // polygon, whether it got one.
    std::vector<std::uint8_t> add_skirts(Draw& d, std::uint32_t element, const std::vector<Polygon>& polygons, float z);

    // ReconstructOptions::texel_margin (texel_margin.cpp): a skirt around
    // boundary polygons, clipped to the rect, but none around a polygon
    // marked in `skirted` (it has a coverage skirt); opaque polygons pulled in.
    void add_texel_skirts(Draw& d, std::uint32_t element, const std::vector<Polygon>& polygons, float z,
                          const std::vector<std::uint8_t>* skirted = nullptr);
    // An opaque polygon of the element's analysis as drawn: moved out to the
    // rect's sides where its placement allows (opaque_to_rect_sides; not when
    // capturing templates, whose placement is not known), then pulled in,
    // but not off those sides (side_margins).
    Polygon pull_inward(std::uint32_t element, const Polygon& p) const;
    // The texel margin for `element`: texel_margin_, grown where the
    // element is scaled below 1/8 (texel_margin.cpp).
    double element_texel_margin(std::uint32_t element) const;

private:
    void add_convex_piece(Draw& d, std::uint32_t element, const Polygon& piece, float z);
    int add_joined_skirt(Draw& d, std::uint32_t element, const Polygon& p, const std::vector<Vec2>& normal,
                          const std::vector<Vec2>& offset, const std::vector<std::uint8_t>& reflex, double m, float z);
    void add_polygon(Draw& d, std::uint32_t element, const Polygon& p, const std::vector<std::uint32_t>& triangles, float z);
    const Scene& scene_;
    std::uint32_t first_map_;
    double margin_;
    double texel_margin_;
    bool spans_;
    TexelMesh* capture_ = nullptr;
    bool always_skirt_ = false;
    bool joined_ = false;
    std::vector<std::uint8_t> dilated_;
    const ClippedParts* clipped_ = nullptr;
    const MergedTiles* merged_ = nullptr;
    std::vector<std::uint32_t> fan_;
    std::unordered_map<const Polygon*, std::vector<std::uint32_t>> triangulated_;
};

// Opaque-pass draws for `elements` (with their levels), one per mesh key,
// front to back: keys by their nearest element, elements nearest first
// within a draw, so the depth test rejects as early as it can.
void append_opaque_draws(const Scene& scene, const std::vector<std::uint32_t>& elements, const std::vector<std::int64_t>& levels,
                         const ElementShapes& shapes, const std::vector<const ImageAnalysis*>& analyses,
                         const std::vector<std::int32_t>& keys, std::int64_t denominator, MeshBuilder& builder,
                         std::vector<Draw>& draws);

void finish_stats(SceneMeshes& out);

// ReconstructOptions::clip_hidden: per element, its blend-pass polygons
// and whole-rect opaque tile with the parts under opaque polygons of
// nearer elements cut away, where that pays (clip_hidden.cpp). Empty
// without Clipper or when disabled.
ClippedParts clip_hidden_parts(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses, const ElementShapes& shapes,
                               const std::vector<std::int64_t>& levels, const ElementGraph& graph,
                               const std::vector<std::int32_t>& keys, const MeshBuilder& builder,
                               const ClipHiddenOptions& options);

// ClipHiddenOptions::memo: made here, kept by the caller for the frames of
// one scene (choose_for_target), one reconstruction at a time.
struct ClipMemoDelete {
    void operator()(ClipMemo* memo) const;
};
std::unique_ptr<ClipMemo, ClipMemoDelete> make_clip_memo();
// How many cuts `memo` gave again instead of making them (tests).
std::int64_t clip_memo_reused(const ClipMemo& memo);

// Issue 25, ReconstructOptions::depthless (depthless.cpp): per element, 1
// when its opaque polygons may lie in front of what an element behind draws
// in the blend pass (screen boxes), so it draws them in the blend pass.
std::vector<std::uint8_t> opaque_in_blend_pass(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                                               const ElementShapes& shapes, const ElementGraph& graph, const MeshBuilder& builder);
// Without depth a merged block is drawn at its leader's place in `order`:
// blocks whose tiles have a neighbour (graph edge) behind them drawn after
// the leader, or in front of them drawn before it, are drawn tile by tile
// again, as are blocks with chained tiles (their edges are not all there)
// or tiles drawn in the blend pass (`moved`).
void keep_merged_in_order(const ElementGraph& graph, const std::vector<std::uint32_t>& order, const std::vector<std::uint8_t>& moved,
                          MergedTiles& merged);
// Both passes in `order` (painter's, batched), for drawing without depth:
// the opaque pass back to front, then the blend pass, where elements
// marked in `moved` also draw their opaque polygons. Vertices keep their
// levels' depth values.
void append_depthless_draws(const Scene& scene, const std::vector<std::uint32_t>& order, const std::vector<std::int64_t>& levels,
                            std::int64_t denominator, const ElementShapes& shapes, const std::vector<const ImageAnalysis*>& analyses,
                            const std::vector<std::int32_t>& keys, const std::vector<std::uint8_t>& moved, MeshBuilder& builder,
                            std::vector<Draw>& draws);

// ReconstructOptions::merge_opaque: blocks of whole-rect opaque tiles at one
// level whose rects lie on screen as in the image (opaque_merge.cpp).
// Tiles cut by `clipped` (may be null) stay apart.
MergedTiles merge_opaque_tiles(const Scene& scene, const ElementShapes& shapes, const std::vector<std::int64_t>& levels,
                               const std::vector<std::int32_t>& keys, const ClippedParts* clipped);

} // namespace depthcull::detail
