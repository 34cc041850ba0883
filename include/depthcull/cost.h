// depthcull: the cost model (issue 14). Predicts a frame's time on one
// renderer from what reconstruction knows, and chooses the analysis of
// each image and element that minimizes it. Pure: no I/O, no exceptions;
// profiles are read and written by depthcull::io (target.h).
// docs/cost-model.md states every term.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "depthcull/analyze.h"
#include "depthcull/scene.h"

namespace depthcull {

// What a frame costs on one renderer, term by term. Every field is a
// finite, non-negative number; times are of one thread of CPU (llvmpipe)
// or of the GPU's frame (a fit like ipad1's).
struct CostProfile {
    std::string name;          // "llvmpipe", "ipad1", or a calibrated renderer's
    std::string renderer;      // what was measured ("llvmpipe (LLVM 15...), OpenGL 4.5 ...")
    std::string source;        // how the numbers were obtained (calibration, fit to Table 2)
    double frame_us = 0;                    // fixed cost of a frame (swap, state, the game's own work)
    double clear_color_ns_per_pixel = 0;    // glClear of the colour buffer
    double clear_depth_ns_per_pixel = 0;    // glClear of the depth buffer (frames with an opaque pass)
    double draw_call_us = 0;                // one glDrawElements with unchanged state
    double texture_switch_us = 0;           // extra when the draw binds another texture than the one before
    double triangle_us = 0;                 // one triangle's set-up
    double triangle_perimeter_ns_per_pixel = 0; // per pixel of perimeter (rasterizers walk edges in blocks)
    double fragment_opaque_ns = 0;          // an opaque-pass fragment that passes the depth test (written)
    double fragment_blend_ns = 0;           // a blend-pass fragment shaded and blended
    double fragment_rejected_ns = 0;        // a fragment the depth test rejects (either pass)
};

// The built-in profiles: "llvmpipe" (Mesa's CPU rasterizer, one thread,
// calibrated on a 2-core EPYC) and "ipad1" (the paper's Table 2 fit).
// Returns false for another name.
bool builtin_profile(const std::string& name, CostProfile* out);
std::vector<std::string> builtin_profile_names();
// True when every term is finite and >= 0; else *what names the first bad one.
bool profile_is_complete(const CostProfile& p, std::string* what = nullptr);

// What the model reads off a frame's meshes.
struct FrameFeatures {
    std::int64_t pixels = 0;             // viewport width x height
    bool depth_clear = false;            // the meshes use the depth buffer
    std::int64_t draw_calls = 0;
    std::int64_t texture_switches = 0;   // draws whose image differs from the previous draw's (the first counts)
    std::int64_t triangles = 0;
    double triangle_perimeter = 0;       // screen pixels, summed over triangles
    std::int64_t opaque_fragments = 0;   // opaque pass: fragments written
    std::int64_t blend_fragments = 0;    // blend pass: fragments shaded
    std::int64_t rejected_fragments = 0; // either pass: fragments the depth test rejected
    // 4x4 pixel blocks the triangles cover, per pass (OverdrawStats): not
    // priced by a profile yet; measured beside the time for scripts/fit-profile
    // --blocks, the block model docs/ideal-frame.md section 9 proposes.
    std::int64_t opaque_blocks = 0, blend_blocks = 0;
};

// Counts the features of `meshes` by rasterizing them with analyze_overdraw
// (depthcull/overdraw.h: GL's fill rule, 24-bit depth, GREATER from 0 as
// depthcull::runtime draws), the rasterizer the overdraw figures come from.
// opaque_blocks and blend_blocks only when `count_blocks`.
FrameFeatures frame_features(const SceneMeshes& meshes, bool count_blocks = false);

// Predicted milliseconds per frame, and the same split by term.
double predict_ms(const CostProfile& p, const FrameFeatures& f);
struct CostTerms {
    double frame = 0, clears = 0, draws = 0, triangles = 0, opaque = 0, blend = 0, rejected = 0; // ms
};
CostTerms predict_terms(const CostProfile& p, const FrameFeatures& f);

// The paper's MIN_OPAQUE_AREA for a profile: texels from which a square
// opaque polygon over one layer drawn behind it pays for its two
// triangles, its edges and its own fragments. 64 for the paper's iPad
// is of the same order as what ipad1 gives.
int min_opaque_area(const CostProfile& p);

// ReconstructOptions::clip_hidden for a profile (issue 25): enabled, with
// the profile's rejected-fragment, triangle and perimeter costs (ns), so an
// element is cut where the rejected fragments saved beat the triangles and
// edges added. On a renderer that rejects for free (ipad1) nothing pays.
ClipHiddenOptions clip_hidden_options(const CostProfile& p);

// Issue 25 point 1: the limit. The features of the ideal frame: exactly
// ideal_overdraw's fragments (depthcull/overdraw.h), in one pass (blended,
// no depth buffer), one draw per texture, nothing rejected, and the fewest
// triangles: two per element that shows a fragment (its rect, clipped to
// the viewport for the perimeter). predict_ms of it is the frame time no
// reconstruction of the scene can beat on that renderer, by the model.
// opaque_blocks and blend_blocks: ideal_overdraw's blocks, the 4x4 blocks
// that frame's triangles shade on llvmpipe (no profile prices them; they
// are set beside a frame's). images[i] holds Scene::images[i]'s texels.
FrameFeatures limit_features(const Scene& scene, const std::vector<ImageView>& images);
inline double limit_ms(const CostProfile& p, const Scene& scene, const std::vector<ImageView>& images) {
    return predict_ms(p, limit_features(scene, images));
}

// ---- Least squares (the Table 2 fit, calibration)

// Solves min |X b - y|^2 (rows of X are observations); false when X'X is
// singular. r2: the coefficient of determination, when given.
bool least_squares(const std::vector<std::vector<double>>& x, const std::vector<double>& y, std::vector<double>* b,
                   double* r2 = nullptr);

// One row of the paper's Table 2 (tests/data/paper-table2.tsv).
struct Table2Row {
    std::string scene, mode; // mode: unoptimized, meshes_only, optimized
    double objects = 0, triangles = 0, overdraw = 0, fps = 0;
};
// Frame time (1000 / FPS ms) = a + b * Obj + c * Tri + d * OD, fitted by
// least squares; the profile gets frame_us = a, draw_call_us = b,
// triangle_us = c and fragment costs d / (1024 x 768) (the iPad's screen).
struct Table2Fit {
    double ms = 0, ms_per_draw = 0, ms_per_triangle = 0, ms_per_overdraw = 0;
    double r2 = 0;
    CostProfile profile;
};
bool fit_table2(const std::vector<Table2Row>& rows, Table2Fit* out);

// ---- Choosing for a target (--target)

// Per distinct image rect (a "key"): the analyses to choose among, each
// made with other options (vertex budgets), as analyze_image returns them
// (boundary and opaque polygons; the opaque polygons of every candidate
// are taken from candidates.back(), which must hold the most).
struct TargetCandidates {
    std::vector<const ImageAnalysis*> analyses;
    std::vector<int> max_vertices; // per candidate, for reports
};

// The vertex budgets each image rect is analyzed at for a target: 4, 6, 8
// below the cap, then the cap (max_vertices, at least
// kMinBoundaryVertices). pipeline::plan_target and the wasm reconstruction
// both plan with these, so their choices agree.
std::vector<int> target_budgets(int max_vertices);

// Most opaque pieces per image rect the target's cover plan analyzes
// (OpaqueMethod::cover, issue 25).
inline constexpr int kCoverPlanPolygons = 64;

struct TargetChoice {
    // What reconstruct_scene should take: each chosen analysis once, and
    // per element an index into them (analysis.of(i) is nullptr where the
    // input had none). Indices, not pointers, so a copy stands alone.
    SceneAnalysis analysis;
    bool opaque_pass = true;               // ReconstructOptions::opaque_polygons
    bool depthless = false;                // ReconstructOptions::depthless: drawn without a depth buffer
    // Per key: the chosen candidate (-1: the element's whole rect).
    std::vector<int> key_choice;
    std::int64_t elements_dropped = 0;     // hidden by opaque polygons in front
    std::int64_t elements_opaque = 0;      // drawing opaque polygons
    std::int64_t elements_reverted = 0;    // per-element fallback: opaque polygons given up (step 5)
    std::string fallback;                  // "" or what was given up to stay no slower than meshes only
    // Predicted ms: the chosen output, meshes only, overpaint.
    double predicted_ms = 0, meshes_only_ms = 0, overpaint_ms = 0;
};

// Chooses, to minimize predicted frame time on `profile`: per key the
// boundary (a candidate or the whole rect), per element whether its opaque
// polygons are drawn (all, the largest, or none) and whether it is dropped
// because one opaque polygon in front hides all it draws (exactly: the
// look never changes). Never predicted slower than rectangle_meshes:
// falls back to fewer opaque polygons, then to rects. element_key[i]
// indexes `candidates` (-1: the element has no analysis). Deterministic.
TargetChoice choose_for_target(const Scene& scene, const std::vector<TargetCandidates>& candidates,
                               const std::vector<int>& element_key, const CostProfile& profile,
                               const ReconstructOptions& options);

} // namespace depthcull
