// depthcull: scenes, elements and their reconstruction into meshes
// (paper 2.3).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "depthcull/analyze.h"
#include "depthcull/geometry.h"
#include "depthcull/image.h"
#include "depthcull/limits.h"

namespace depthcull {

// How an element combines with what is behind it (s = texel * colour; GL factors: docs/engine-integration.md):
// alpha    s*a + dst*(1-a)           (the paper's case; may get opaque polygons)
// add      s*a + dst
// multiply dst*(s*a + 1-a)           (s*dst where the texel is opaque, dst where transparent)
// opaque   s                         (texel alpha ignored: the whole rect is opaque)
enum class Blend { alpha, add, multiply, opaque };

// The part of the world the frame shows: world [x, x+width) x [y, y+height)
// maps to framebuffer pixels [0, width) x [0, height), y down.
struct Viewport {
    double x = 0, y = 0;
    int width = 0, height = 0;
};

struct SceneImage {
    std::string id;
    std::string path;         // as loaded (absolute or relative to the cwd)
    int width = 0, height = 0;
    // A colour key (Tiled's `trans`, 0xRRGGBB): texels of exactly this
    // colour are transparent, applied when the file is decoded. The file
    // on disk does not say so, so scene and mesh files carry the key.
    bool has_trans = false;
    std::uint32_t trans = 0;
    // A solid colour and no file (Tiled's map backgroundcolor): path is
    // empty, every texel is 0xRRGGBB and opaque, kFillImageSide square (big
    // enough that its opaque polygon passes the worth-it area threshold).
    bool has_fill = false;
    std::uint32_t fill = 0;
};
inline constexpr int kFillImageSide = 16;

// Paper 2: an element is an image (a rect of it) placed on screen.
struct Element {
    int image = 0;            // index into Scene::images
    Rect rect;                // source texels; always resolved (never empty in a valid scene)
    // SVG/canvas matrix [a b c d e f]: screen = (a*u + c*v + e, b*u + d*v + f),
    // (u, v) in texels of rect with its top-left at the origin.
    std::array<double, 6> transform{1, 0, 0, 1, 0, 0};
    std::array<float, 4> color{1, 1, 1, 1}; // multiplier, 0..1
    Blend blend = Blend::alpha;
    // Index into Scene::animations, or -1: the element shows those frames
    // in turn (its image and rect are frame 0's). Its analysis covers every
    // frame: boundary polygons hold the union of the frames' non-transparent
    // texels, opaque polygons only texels opaque in all of them, so the
    // optimized meshes draw any frame correctly with the UVs moved to it.
    int animation = -1;
};

// An animation (Tiled's animated tiles): frames of one size, each a rect of
// an image shown for duration_ms.
struct AnimationFrame {
    int image = 0; // index into Scene::images
    Rect rect;
    int duration_ms = 0;
};
struct Animation {
    std::vector<AnimationFrame> frames;
};

// An animation's one analysis runs on animation_alpha's image: the frames'
// alpha combined (0 where every frame is transparent, 255 where every frame
// is opaque, 128 elsewhere), so boundary polygons hold the union of the
// frames' non-transparent texels and opaque polygons only texels opaque in
// all. place_animation_analysis then moves its polygons onto frame 0's
// rect and asks each frame's page whether edges bleed
// (src/scene/animation_frames.cpp).
Image animation_alpha(const std::vector<ImageView>& images, const Animation& animation);
void place_animation_analysis(ImageAnalysis& analysis, const std::vector<ImageView>& images, const Animation& animation);

// Where moving sprites go between a static scene's elements (depthcull/
// frame.h): before scene.elements[element] (elements.size(): on top), with
// `levels` depth levels reserved for them, so at most that many sprites a
// frame. Given in ReconstructOptions::insertion_points (element and levels,
// ascending elements); SceneMeshes::insertion_points adds what
// reconstruction made of them.
struct InsertionPoint {
    std::size_t element = 0;
    std::int64_t levels = 0;
    std::int64_t first_level = 0;  // the first reserved level
    std::uint32_t blend_draw = 0;  // static draws from this one on are drawn after the point's sprites

    friend bool operator==(const InsertionPoint&, const InsertionPoint&) = default;
};

// Elements in painter's order: elements[0] is farthest back.
struct Scene {
    Viewport viewport;
    Filter filter = Filter::nearest; // how the renderer samples textures
    std::vector<SceneImage> images;
    std::vector<Element> elements;
    std::vector<Animation> animations; // what Element::animation indexes
    // Where a game draws its moving sprites (depthcull/frame.h): element
    // indices, ascending; sprites go before elements[i] (elements.size():
    // on top). Tiled maps: the end of each object layer. For
    // ReconstructOptions::insertion_points.
    std::vector<std::size_t> insertion_points;
};

// Screen position of texel-space point p (relative to the rect's top-left).
inline Vec2 apply(const std::array<double, 6>& m, Vec2 p) {
    return {m[0] * p.x + m[2] * p.y + m[4], m[1] * p.x + m[3] * p.y + m[5]};
}

// ---- Meshes (paper 2.3.3)

enum class Pass {
    opaque, // depth test + write, blending off, drawn front to back
    blend,  // depth test (when the output has opaque draws), blending on, back to front
};

// Vertex layout: x, y (screen pixels), z (0..1, larger is nearer),
// u, v (0..1 of the whole image), r, g, b, a (colour multiplier).
inline constexpr int kVertexFloats = 9;

// Where on the image an element's pixels come from: the texel position
// (texels of the whole image, not 0..1) of screen point (x, y), exact in
// double. u = u0 + ux*x + uy*y, v = v0 + vx*x + vy*y.
// `rect` is the element's rect: the texels it may show (a renderer draws
// nothing where the map leads outside it).
struct TexelMap {
    double u0 = 0, ux = 1, uy = 0;
    double v0 = 0, vx = 0, vy = 1;
    Rect rect;
};

// The map of e's rect as GL sees it: solved, in double, from the float
// screen positions of the rect's corners (0, 0), (w, 0), (0, h), the
// vertices overpaint draws. Every way of drawing an element (overpaint's
// rect, meshes only, boundary and opaque polygons, dynamic elements) takes
// its map from this one function, so a renderer that samples through it
// shows the same texel at every pixel whatever triangles cover it. From the
// float corners rather than the transform's inverse: a quarter turn built
// with cos and sin has entries like 6e-17 that float corners round away,
// so a pixel centre on a texel edge stays exactly on it and the renderer's
// tie rule agrees with GL's fill rule. A transform that collapses the rect
// (the element draws nothing) gives a map of zeros at the rect's origin.
TexelMap texel_map(const Element& e);

// A run of a draw's vertices that one element drew: from first_vertex up
// to the next span's first vertex (or the draw's end).
struct ElementSpan {
    std::uint32_t element = 0;      // index into Scene::elements (dynamic elements follow the static ones)
    std::uint32_t first_vertex = 0;
};

struct Draw {
    int image = 0;            // index into Scene::images
    Pass pass = Pass::blend;
    Blend blend = Blend::alpha;
    std::vector<float> vertices;        // kVertexFloats per vertex
    std::vector<std::uint32_t> indices; // triangles
    // Which element each run of vertices comes from (a triangle never
    // mixes elements), in vertex order. Filled only when asked
    // (ReconstructOptions::element_spans): a renderer that samples through
    // each element's texel_map (render::GlRenderer, proving pixel identity)
    // needs it, an engine does not. The mesh file formats do not carry it.
    std::vector<ElementSpan> element_spans;

    std::size_t vertex_count() const { return vertices.size() / kVertexFloats; }
    std::size_t triangle_count() const { return indices.size() / 3; }
};

// The analyzer of reconstruction. Best cases: draw_calls == number of
// distinct (image, blend) pairs; depth_levels == longest overlap chain.
struct SceneStats {
    std::int64_t elements = 0;
    std::int64_t draw_calls = 0;
    std::int64_t triangles = 0;
    std::int64_t depth_levels = 0;  // distinct element depth values used
    std::int64_t graph_edges = 0;
    // Bits a depth buffer needs to resolve every z this output uses (see
    // depth_z); <= 16 fits a 16-bit buffer, never more than 24.
    std::int64_t depth_bits = 0;
    // No wall time: the same scene and options give the same stats on every
    // run; the reconstruction's time is measured by the caller (optimize,
    // dc_reconstruct) and written into the mesh files beside them.

    friend bool operator==(const SceneStats&, const SceneStats&) = default;
};

struct SceneMeshes {
    Viewport viewport;
    bool depth_test = false;  // false for overpaint and meshes-only output
    // The texture filter the meshes are correct for (Scene::filter, which
    // the analysis was made for): their guarantee holds only when drawn
    // with it, so the mesh files carry it.
    Filter filter = Filter::nearest;
    std::vector<Draw> draws;  // in the order to draw them
    SceneStats stats;
    // D of depth_z: the z values are (2k+1)/D and (2k+2)/D. 0 when the
    // meshes have no depth values (overpaint, meshes only). Reconstruction
    // sets it, the mesh readers from stats.depth_bits (D = 2^(bits-2)).
    std::int64_t depth_denominator = 0;
    // ReconstructOptions::insertion_points as reconstructed (depthcull/frame.h).
    std::vector<InsertionPoint> insertion_points;
};

// texel_map of every element, indexed as ElementSpan::element names them
// (for dynamic elements, append theirs after the scene's).
std::vector<TexelMap> element_maps(const Scene& scene);

// ---- Reconstruction (paper 2.3)

enum class GraphMode {
    polygons, // elements overlap when their transformed boundary polygons do (default)
    boxes,    // when their transformed rects do (the paper's simple test; for comparison)
};

enum class SortMethod {
    none,  // keep painter's order
    paper, // SortElements of paper 2.3.1
    batch, // ours: topological order preferring the current mesh; the default
};

// 1/32 texel: 1/256 pixel at a scale of 1/8, twice llvmpipe's worst
// vertex snapping error (ReconstructOptions::texel_margin).
inline constexpr double kTexelMargin = 1.0 / 32;

// Issue 25: clipping hidden parts. Where opaque polygons of elements in
// front (drawn in the opaque pass, at a nearer depth level) cover part of
// an element's blend-pass polygons or of a whole-rect opaque tile, that
// part is cut away on the CPU (Clipper 6, exact integers), so neither its
// blended nor its rejected fragments are drawn. Per element, only when
// saved fragments x fragment_cost beat the added triangles x
// triangle_cost plus the added summed triangle perimeter (screen pixels)
// x perimeter_cost (units of the caller's choice; the cost model fills
// them from a profile: clip_hidden_options in depthcull/cost.h). The cut
// runs `margin` screen pixels inside the occluder, so GL's vertex snapping
// never uncovers a pixel (src/scene/clip_hidden.cpp). Elements whose
// transform GL snaps exactly (power-of-two scales, quarter turns, flips,
// 1/256-pixel moves) are clipped anywhere; others (turned, scaled anyhow)
// only `margin` inside their rect. What is left is triangulated whole,
// holes included. Without Clipper (wasm builds) it does nothing.
namespace detail {
struct ClipMemo;  // src/scene/clip_hidden.cpp
struct GraphMemo; // src/scene/element_graph.cpp
}

struct ClipHiddenOptions {
    bool enabled = false;
    double fragment_cost = 1;
    double triangle_cost = 0;
    double perimeter_cost = 0;
    double margin = 1.0 / 16;
    // For choose_for_target (depthcull/cost.h): price what opaque
    // polygons hide as clipped away (free) rather than rejected.
    bool plan_occluders = false;
    // Internal, for choose_for_target, which reconstructs dozens of frames
    // of one scene that cut most elements alike: where it keeps each
    // element's last cut, reused when the element is cut with the same
    // polygons by the same occluders again. Null: none.
    detail::ClipMemo* memo = nullptr;
};

struct ReconstructOptions {
    GraphMode graph = GraphMode::polygons;
    SortMethod sort = SortMethod::batch;
    bool opaque_polygons = true; // false: no opaque pass at all
    // Depth levels kept free in front of the static scene for dynamic
    // elements (add_dynamic_elements); beyond the paper.
    std::int64_t reserved_dynamic_levels = 0;
    // Drop elements entirely outside Scene::viewport (they draw no pixel in
    // that frame). Off by default: engines usually scroll the camera over
    // the meshes.
    bool cull_to_viewport = false;
    // Screen pixels by which what alpha / add / multiply elements draw in
    // the blend pass (boundary polygons or rect) is grown, by a skirt of
    // extra triangles around each polygon (its own triangles stay as they
    // are); overpaint_meshes takes the same margin. For renderers that sample through
    // element_maps (Draw::element_spans) and output alpha 0 for a texel position
    // outside the element's rect (render::GlRenderer): GL snaps vertices
    // (llvmpipe to 1/256 pixel), so a pixel centre that close to a polygon
    // edge may be left out although its texel is inside; grown, every such
    // pixel is covered, and the extra fragments sample transparent texels
    // or fall outside the rect, changing nothing. 0 (no skirt) for meshes
    // an engine draws: without the rect test an edge pixel could sample the
    // neighbouring atlas frame. A polygon closer than 3 margins to another
    // of its element's polygons (or to itself) gets no skirt, which would
    // blend the other's texels twice.
    double coverage_margin = 0;
    // Texels by which boundary polygons are grown (a skirt of triangles
    // around them, clipped to the element's rect) and opaque polygons
    // pulled in, so that a plain renderer (texture x colour, nearest
    // filtering; depthcull::runtime, an engine's sprite shader) draws the
    // optimized meshes pixel for pixel like overpaint despite GL's vertex
    // snapping. See src/scene/texel_margin.cpp for why kTexelMargin; 0
    // turns it off (the paper's meshes exactly).
    double texel_margin = kTexelMargin;
    // Candidate pairs the element graph may compare (limits::kGraphPairBudget;
    // docs/element-graph.md): past it, crowded spots keep painter's order
    // among their elements (correct, less batching), so a pile of sprites
    // costs linear time and memory. Edges <= graph_pair_budget + 2n.
    std::uint64_t graph_pair_budget = limits::kGraphPairBudget;
    // Internal, for choose_for_target, whose contestant frames mostly draw
    // the same boundary polygons (they differ in opaque polygons, dropped
    // elements, the depth buffer): where graphs built for one scene are
    // kept with what they were built from, and an equal build is answered
    // from. Null: none.
    detail::GraphMemo* graph_memo = nullptr;
    // Fill Draw::element_spans (for renderers that sample through texel
    // maps); off for engines and files.
    bool element_spans = false;
    // Depth ranges reserved between the elements for moving sprites
    // (InsertionPoint; FrameAssembler::assemble_at). Static elements before
    // a point stay behind its sprites, those after it in front, and no
    // blend draw spans a point. Ascending `element`, each <= elements.
    std::vector<InsertionPoint> insertion_points;
    ClipHiddenOptions clip_hidden; // off by default (issue 25)
    // Issue 25: whole-rect opaque tiles at one depth level that lie on
    // screen as their rects lie in the image (a backdrop cut into tiles)
    // are drawn as one quad per block (src/scene/opaque_merge.cpp): fewer
    // triangles and edges, the same pixels. Only for plain renderers: not
    // with element_spans or coverage_margin (their rect test would cut the
    // quad). Off by default; --target turns it on.
    bool merge_opaque = false;
    // Issue 25: no depth buffer (docs/ideal-frame.md section 10). The
    // opaque pass is drawn back to front (the blend pass's order, which
    // keeps every element behind the ones it overlaps), so the nearest
    // opaque polygon is written last, and an element whose opaque polygons
    // lie in front of another's blend-pass polygons draws them in the blend
    // pass instead (blended: its texels there are opaque, so blending writes
    // what the opaque pass would). Then nothing the depth test would reject
    // is drawn over what it hides, and the frame needs no depth clear or
    // test: SceneMeshes::depth_test is false. Only without insertion
    // points, element spans and coverage skirts (their sprites and rect
    // tests need the depth test); a merged block of opaque tiles is kept
    // only where its leader's place in the order suits all its tiles. Off
    // by default; the --target planner turns it on where the frame is
    // predicted faster.
    bool depthless = false;
};

// Whether reconstruct_scene honours ReconstructOptions::depthless with the
// rest of `options`: an opaque pass, and no insertion points, element spans
// or coverage skirts.
inline bool depthless_possible(const ReconstructOptions& options) {
    return options.opaque_polygons && options.insertion_points.empty() && !options.element_spans && !(options.coverage_margin > 0);
}

enum class ReconstructStatus {
    ok,
    invalid_scene,         // an element names a missing image or analysis, NaN transform, ...
    too_many_depth_levels, // more depth levels than a 24-bit depth buffer resolves
};

// The per-image analyses of a scene's elements, as a value: each distinct
// (image file, rect) analyzed once, elements naming theirs by index, so a
// copy is whole (no pointers into itself). What the pipeline
// (depthcull/pipeline.h) produces and reconstruction reads.
struct SceneAnalysis {
    std::vector<ImageAnalysis> images;     // one per distinct (image file, rect)
    std::vector<std::uint32_t> of_element; // per element: index into images
    // Element i's analysis; nullptr past either vector.
    const ImageAnalysis* of(std::size_t element) const {
        return element < of_element.size() && of_element[element] < images.size() ? &images[of_element[element]] : nullptr;
    }
    // of() for every element: the per-element form the functions below
    // also take (valid while this value lives unchanged).
    std::vector<const ImageAnalysis*> per_element() const {
        std::vector<const ImageAnalysis*> out(of_element.size());
        for (std::size_t i = 0; i < out.size(); ++i) out[i] = of(i);
        return out;
    }
};

// Paper 2.3. analyses[i] is the per-image analysis of elements[i]'s rect
// (elements sharing an image rect may share one ImageAnalysis). On success
// `out` holds the draws in drawing order. The per-element form serves
// callers that own each element's analysis themselves (the C API,
// dynamic elements).
ReconstructStatus reconstruct_scene(const Scene& scene, const SceneAnalysis& analysis, const ReconstructOptions& options,
                                    SceneMeshes* out);
ReconstructStatus reconstruct_scene(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                                    const ReconstructOptions& options, SceneMeshes* out);

// Table 2 "Meshes only": 2.3's sorting and batching with every element's
// whole rect and no opaque polygons (no depth test).
ReconstructStatus rectangle_meshes(const Scene& scene, const ReconstructOptions& options, SceneMeshes* out);

// The stats of rectangle_meshes and overpaint_meshes (coverage margin 0)
// counted without building a vertex: draw calls, triangles, graph edges.
// What `optimize` reports beside its own output.
ReconstructStatus rectangle_stats(const Scene& scene, const ReconstructOptions& options, SceneStats* out);
SceneStats overpaint_stats(const Scene& scene);

// ---- The stages of reconstruction, exposed for tests, tools and engines.

// Paper 2.3: the element graph. Element i is in front of element j < i
// when they overlap as drawn; behind(i) lists those j in ascending order.
// Elements that draw nothing (empty boundary) have no edges.
struct ElementGraph {
    std::vector<std::uint32_t> offsets{0}; // size() + 1 entries
    std::vector<std::uint32_t> targets;
    // Past the pair budget: 1 for the elements of crowded cells, ordered by
    // a chain in painter's order instead of compared, so an element they
    // overlap is reached by a path, not always an edge (empty when none).
    std::vector<std::uint8_t> chained;

    std::size_t size() const { return offsets.size() - 1; }
    bool is_chained(std::size_t i) const { return i < chained.size() && chained[i]; }
    std::size_t edge_count() const { return targets.size(); }
    const std::uint32_t* behind_begin(std::size_t i) const { return targets.data() + offsets[i]; }
    const std::uint32_t* behind_end(std::size_t i) const { return targets.data() + offsets[i + 1]; }
    bool has_edge(std::size_t front, std::size_t back) const; // binary search
    // The edges reversed: per element, those in front of it, ascending.
    std::vector<std::vector<std::uint32_t>> in_front() const;
};

// Builds the graph with a uniform grid (broad phase) and a conservative
// polygon overlap test (narrow phase); near-linear in practice. Null or
// invalid analyses count as drawing nothing.
// At most pair_budget candidate pairs are compared (ReconstructOptions::
// graph_pair_budget): see docs/element-graph.md for the bound.
ElementGraph build_element_graph(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses, GraphMode mode,
                                 std::uint64_t pair_budget = limits::kGraphPairBudget);
ElementGraph build_element_graph(const Scene& scene, const SceneAnalysis& analysis, GraphMode mode,
                                 std::uint64_t pair_budget = limits::kGraphPairBudget);

// Paper 2.3.1: a drawing order (a permutation of element indices) that
// never moves an element across one it overlaps. SortMethod::batch returns
// the order with the fewest blend-pass draws among ours and (for scenes of
// up to kPaperSortMaxElements) the paper's.
inline constexpr std::size_t kPaperSortMaxElements = 4096;
std::vector<std::uint32_t> sort_elements(const Scene& scene, const ElementGraph& graph, SortMethod method);
// Draws a drawing order needs: runs of elements that share a mesh.
std::int64_t count_batches(const Scene& scene, const std::vector<std::uint32_t>& order);
// Elements that can share a mesh (paper's CanShareMesh): same image file
// (image entries with equal paths share) and same blend mode.
bool can_share_mesh(const Scene& scene, const Element& a, const Element& b);

// Paper 2.3.2, by longest path: level[i] = 1 + max level of the elements i
// is in front of (0 when none), so overlapping elements never share a
// level and the range stays as small as the graph allows.
std::vector<std::int64_t> assign_depth_levels(const ElementGraph& graph);

// Depth mapping: with D = depth_denominator(total levels), an element at
// level k draws its boundary polygons at z = (2k+1)/D and its opaque
// polygons at z = (2k+2)/D (the paper's k + epsilon), larger z nearer,
// GL_GREATER, cleared to 0. D is a power of two >= 2*levels + 2, at least
// 256; every z is exact in a float, and neighbouring values are at least
// 2^(bits-log2 D) units of a `bits`-bit depth buffer apart.
inline constexpr std::int64_t kMaxDepthLevels = (std::int64_t(1) << 21) - 1;   // 24-bit buffer, 4 units apart
inline constexpr std::int64_t kMaxDepthLevels16 = (std::int64_t(1) << 13) - 1; // 16-bit buffer, 4 units apart
std::int64_t depth_denominator(std::int64_t levels);
inline float depth_z(std::int64_t level, bool opaque, std::int64_t denominator) {
    return float(double(2 * level + (opaque ? 2 : 1)) / double(denominator));
}
// The levels the draws' z values use under denominator D (one past the
// highest level drawn; 0 for none): what SceneStats::depth_levels states
// for meshes this library made, derived rather than trusted where the
// meshes come from a file or a caller.
std::int64_t depth_levels_of_draws(const std::vector<Draw>& draws, std::int64_t denominator);

// Triangles of a simple polygon, clockwise or not, with collinear
// vertices allowed: indices into `polygon`. Up to 64 vertices on a 1/256
// grid, the triangulation with the least total diagonal length (every
// edge costs a renderer that shades 4x4 blocks; issue 25); otherwise ear
// clipping (paper 2.3.3, Held's FIST ear conditions). Exact for vertices
// on the texel grid.
std::vector<std::uint32_t> triangulate_polygon(const Polygon& polygon);

// ---- Dynamic elements (beyond the paper, section 4 caveat 2)
//
// Moving elements drawn on top of an optimized static scene, each frame.
// The static scene is reconstructed with reserved_dynamic_levels = R; the
// dynamic elements of a frame (at most R, in painter's order) take levels
// static_levels .. static_levels + R - 1 in drawing order, so they are in
// front of every static element and of each other as listed, with no graph
// needed. Their opaque polygons join the opaque pass; their boundary
// polygons are drawn after the static blend pass, consecutive elements that
// share a mesh in one draw. R elements always fit (the depth mapping may
// leave room for more); more than fit: too_many_depth_levels. `frame` gets
// only the dynamic draws, opaque then blend (each draw's pass says where it
// goes): the dynamic opaque draws come before the static draws (they are
// nearest, so they reject the most), the blend draws after every static
// one; no static draw is copied. frame->stats: static_meshes' with the
// dynamic elements and levels added, draw calls and triangles of the
// dynamic draws alone. With element_spans, spans name dynamic element i
// as static_meshes.stats.elements + i.
ReconstructStatus add_dynamic_elements(const SceneMeshes& static_meshes, const Scene& scene,
                                       const std::vector<Element>& elements,
                                       const std::vector<const ImageAnalysis*>& analyses, SceneMeshes* frame,
                                       bool element_spans = false);
// The whole frame as one SceneMeshes (dynamic opaque, static, dynamic
// blend draws), for tests and renderers that take one list; copies.
SceneMeshes compose_frame(const SceneMeshes& static_meshes, const SceneMeshes& dynamic);

// Overpaint (the unoptimized method, Table 2 "Unoptimized"): one draw per
// element, its whole rect as two triangles, in painter's order, no depth.
// coverage_margin: as ReconstructOptions::coverage_margin, around every
// rect but those of Blend::opaque elements (drawn with blending off, where
// the renderer's rect test would not leave the pixel as it is).
// element_spans: as ReconstructOptions::element_spans.
SceneMeshes overpaint_meshes(const Scene& scene, double coverage_margin = 0, bool element_spans = false);

// A run of a draw's vertices that shows an animated element: an engine
// maps their u, v from frame 0's rect to the current frame's
// (docs/mesh-format.md, "animated").
struct AnimatedRun {
    std::uint32_t draw = 0;
    std::uint32_t first_vertex = 0;
    std::uint32_t vertex_count = 0;
    std::uint32_t animation = 0; // index into the animations
    friend bool operator==(const AnimatedRun&, const AnimatedRun&) = default;
};

// The animated runs of `meshes` (made with ReconstructOptions::element_spans)
// over `scene`: adjacent spans of one element are one run; none without
// animations. The meshes files' writers (io) and the wasm reconstruction
// list these (src/scene/animation_frames.cpp).
std::vector<AnimatedRun> animated_runs(const Scene& scene, const SceneMeshes& meshes);

} // namespace depthcull
