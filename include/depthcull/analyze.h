// depthcull: per-image analysis (paper 2.1 boundary polygons, 2.2 opaque
// polygons) and the analyzers that measure and check it.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "depthcull/geometry.h"
#include "depthcull/image.h"

namespace depthcull {

// How the renderer samples the texture. Nearest: a screen pixel shows one
// texel, so texel squares are what polygons must contain / avoid. Linear:
// bilinear filtering blends each texel into the half texel around its
// square, so the boundary polygon must contain every non-transparent texel
// square grown by half a texel, and opaque polygons must keep half a texel
// away from every non-opaque texel square.
enum class Filter { nearest, linear };

// The least vertex budget that always fits inside the rect (content in all
// four corners of a rect has no containing triangle inside it).
inline constexpr int kMinBoundaryVertices = 4;

// Bumped whenever a change to the analysis (src/boundary, src/opaque) can
// change its output, so the on-disk cache never serves results of an older
// algorithm. tests/cli/test_analysis_version.cpp fails until it is bumped.
inline constexpr int kAnalysisVersion = 4;

// Paper 2.1. MAX_BOUNDARY_VERTICES = 10.
struct BoundaryOptions {
    int max_vertices = 10;        // per polygon; values below kMinBoundaryVertices act as it
    bool split_parts = true;      // beyond the paper (section 4, caveat 1)
};

enum class OpaqueMethod {
    paper, // paper 2.2, the reference implementation
    fast,  // ours, the default: grown convex polygons, guarded by the paper's own sequence (never covers less)
    grow,  // the growth alone: fastest, most coverage on average, without the guard; see docs/opaque.md
    // Beyond the paper (issue 25): the opaque region cut into as many convex
    // pieces (quads) as pay, each worth min_area texels, up to max_polygons;
    // min_coverage does not stop it. Vertices on the 1/16-texel grid, 1/16
    // texel inside the region, so outline texels' centres are covered too.
    cover,
};

// Paper 2.2. MAX_OPAQUE_POLYGONS = 4, MIN_OPAQUE_COVERAGE = 0.75,
// MIN_OPAQUE_AREA = 64.
struct OpaqueOptions {
    OpaqueMethod method = OpaqueMethod::fast;
    int max_polygons = 4;       // paper: MAX_OPAQUE_POLYGONS
    double min_coverage = 0.75; // stop once this fraction of opaque texels is covered
    // Paper: MIN_OPAQUE_AREA. A polygon must reach this many opaque texels
    // that no earlier polygon reached, where it reaches the texels it
    // touches once grown by half a texel (the paper's count: its quad before
    // the half-texel push). The growth also asks min_area / 2 of each vertex
    // it adds. docs/opaque.md relates it to the cost of a polygon.
    int min_area = 64;
};

struct AnalyzeOptions {
    BoundaryOptions boundary;
    OpaqueOptions opaque;
    // The one home of the texture filter an analysis is made for: both
    // stages get it. In a scene pipeline it is the scene's (Scene::filter,
    // which a command line's --filter overrides: io::PrepareOptions).
    Filter filter = Filter::nearest;
};

// The analyzer's figures for one image (or sub-rectangle). Best cases:
// boundary_area == nontransparent_texels (excess ratio 1.0) and
// opaque_coverage == 1.0.
struct ImageStats {
    std::int64_t nontransparent_texels = 0;
    std::int64_t opaque_texels = 0;
    double boundary_area = 0;   // total area of the boundary polygons
    double bbox_area = 0;       // area of the non-transparent bounding box
    int boundary_vertices = 0;  // summed over boundary polygons
    double opaque_area = 0;     // total area of the opaque polygons
    std::int64_t opaque_covered_texels = 0; // opaque texels inside opaque polygons
    double opaque_coverage = 0; // covered / opaque texels (0 when none)
    // No wall time: a value of the core is the same on every run (timing is
    // the caller's: `analyze` times each image, the pipeline the scene).

    friend bool operator==(const ImageStats&, const ImageStats&) = default;

    // boundary area / non-transparent texel area; 1.0 is a perfect fit.
    double excess_area_ratio() const {
        return nontransparent_texels ? boundary_area / double(nontransparent_texels) : 0.0;
    }
};

// Polygons are in texel coordinates of the full image (rect offset added),
// clockwise with y down.
struct ImageAnalysis {
    Rect rect;
    std::vector<Polygon> boundary; // empty for a fully transparent rect
    std::vector<Polygon> opaque;
    ImageStats stats;
    // edges_bleed(image, rect): a turned or scaled element then draws
    // overpaint's rect edges (src/scene/shapes.cpp). Not cached: it
    // depends on texels outside the rect, which the cache key leaves out.
    bool bleeding_edges = false;

    friend bool operator==(const ImageAnalysis&, const ImageAnalysis&) = default;
};

// Paper 2.1: boundary polygons of `rect` in `image`. Guarantee: every
// non-transparent texel square (grown by half a texel with Filter::linear)
// lies inside one of the returned polygons; each polygon is simple and has
// at most options.max_vertices vertices.
std::vector<Polygon> generate_boundary_polygons(ImageView image, Rect rect, const BoundaryOptions& options,
                                                Filter filter = Filter::nearest);

// Most vertices of an opaque polygon (the paper's are quads; ours grow up
// to this many, 6 triangles).
inline constexpr int kMaxOpaqueVertices = 8;

// Paper 2.2: opaque polygons of `rect` in `image`. Guarantee: convex,
// clockwise, at most kMaxOpaqueVertices vertices (half-texel grid; 1/16
// texel with OpaqueMethod::cover), and no polygon overlaps with positive area or touches with an
// edge any non-opaque texel square (kept half a texel away with
// Filter::linear).
std::vector<Polygon> generate_opaque_polygons(ImageView image, Rect rect, const OpaqueOptions& options,
                                              Filter filter = Filter::nearest);

// How hard the opaque search worked (beyond the paper; for benchmarks and
// diagnostics). The paper's search is exponential in the branching of the
// segment graph (2.2.2; section 4, caveat 3), so each method stops searching
// after a fixed amount of work (kPaperOpaqueWorkBudget, kFastOpaqueWorkBudget:
// one unit per candidate quad plus one per texel or row it visits; the fast
// search also charges 32 per heap pop) and keeps
// the best polygons found so far; budget_exhausted then says so. Counting
// work instead of time keeps the output deterministic.
struct OpaqueSearchStats {
    std::int64_t candidates = 0; // candidate polygons evaluated
    std::int64_t work = 0;       // work units spent
    bool budget_exhausted = false;
};
inline constexpr std::int64_t kPaperOpaqueWorkBudget = std::int64_t(4) << 30;
inline constexpr std::int64_t kFastOpaqueWorkBudget = std::int64_t(1) << 26;

// generate_opaque_polygons that also reports the search effort.
std::vector<Polygon> generate_opaque_polygons(ImageView image, Rect rect, const OpaqueOptions& options, Filter filter,
                                              OpaqueSearchStats* stats);

// Both stages plus the stats.
ImageAnalysis analyze_image(ImageView image, Rect rect, const AnalyzeOptions& options);

// ---- Scratch memory. The opaque search holds several bytes per texel of
// the rect (masks, prefix sums, the paper's candidate quads): a 649-byte
// JPEG header can ask for a 16384^2 opaque image, whose search would need
// about 8 GiB. Callers estimate it first and refuse or queue what would not
// fit (pipeline::MemoryBudget runs workers within one budget).

// Most scratch memory one analysis may need (README, "Limits"): an 8192^2
// opaque image fits, the largest image (kMaxImageSide^2) does not.
inline constexpr std::uint64_t kMaxAnalysisBytes = std::uint64_t(2) << 30;

// An upper estimate of the scratch bytes analyze_image allocates for `rect`
// with `options` (the image's own pixels not counted): measured per texel
// for each opaque method, plus the fast search's candidate quads, which its
// work budget bounds. Never 0 for a non-empty rect.
std::uint64_t analysis_scratch_bytes(Rect rect, const AnalyzeOptions& options);

enum class AnalyzeStatus {
    ok,
    over_memory_limit, // analysis_scratch_bytes over the limit given: nothing analyzed
    out_of_memory,     // an allocation failed all the same (a machine with less memory)
};

// analyze_image that refuses, before allocating, a rect whose
// analysis_scratch_bytes exceed `max_scratch_bytes`, and reports a failed
// allocation as a status instead of an exception (the core throws
// nothing). `out` is set only with AnalyzeStatus::ok.
AnalyzeStatus analyze_image(ImageView image, Rect rect, const AnalyzeOptions& options, std::uint64_t max_scratch_bytes,
                            ImageAnalysis& out);

// True when a pixel centre within GL's snapping error of the rect's edge
// may show a non-transparent texel in overpaint: one on the rect's border
// (just inside), or one in the ring of texels just outside it (within the
// image: an atlas page's next frame, which overpaint's quad shows where
// its snapped edge passes a centre just outside the rect; past the image,
// clamping shows the border texel again).
bool edges_bleed(ImageView image, Rect rect);

// ---- Analyzers and checkers (exact; used by tests and `analyze --check`).

// Number of non-transparent texel squares of rect (grown by half a texel
// for Filter::linear) that are not inside any one of `polygons`. 0 is the
// guarantee of generate_boundary_polygons.
std::int64_t count_uncontained_texels(ImageView image, Rect rect, const std::vector<Polygon>& polygons, Filter filter);

// Number of non-opaque texel squares of rect that an opaque polygon
// overlaps with positive area or touches along an edge (for Filter::linear:
// comes within half a texel of). 0 is the guarantee of
// generate_opaque_polygons. Texels outside rect count as non-opaque.
std::int64_t count_opaque_violations(ImageView image, Rect rect, const std::vector<Polygon>& polygons, Filter filter);

// Opaque texels of rect whose square lies inside an opaque polygon.
std::int64_t count_covered_opaque_texels(ImageView image, Rect rect, const std::vector<Polygon>& polygons);
// Opaque texels of rect whose centre lies strictly inside an opaque polygon:
// the pixels the opaque pass draws at 1:1 (issue 25; it pulls polygons in
// by the texel margin, so a centre on an edge is not drawn).
std::int64_t count_centre_covered_opaque_texels(ImageView image, Rect rect, const std::vector<Polygon>& polygons);

} // namespace depthcull
