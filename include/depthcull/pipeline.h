// depthcull: the scene pipeline, the only orchestration layer. One call,
// optimize(), runs a whole optimization (load, settle the filter and the
// profile, decode each image once, analyze each distinct (image, rect) once
// through the on-disk cache on threads, plan for a target, reconstruct)
// and returns it as one value; every command, the C API and the examples
// call it. Its stages (prepare_scene, plan_target) stay public for tests
// and tools. The orchestration lives here so io stays formats only and the
// core stays pure. Like io, everything here may do I/O and throws
// depthcull::Error only.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "depthcull/cost.h"
#include "depthcull/io.h"
#include "depthcull/scene.h"

namespace depthcull::pipeline {

// Scratch memory that analyses running at once may hold together
// (analysis_scratch_bytes each): a worker reserves an analysis's estimate
// before it runs and waits while the others' reservations leave too little,
// so peak memory stays within the budget whatever -j is (at -j 8, eight
// 4096^2 frames would otherwise need 4 GiB at once). Results are stored by
// index, so waiting never changes the output. The budget is also the most
// one analysis may need: a larger one is refused (depthcull::Error naming the
// file, the rect and the limit), never queued.
class MemoryBudget {
public:
    explicit MemoryBudget(std::uint64_t bytes = kMaxAnalysisBytes) : limit_(bytes) {}
    MemoryBudget(const MemoryBudget&) = delete;
    MemoryBudget& operator=(const MemoryBudget&) = delete;
    std::uint64_t limit() const { return limit_; }

    // Bytes held until destroyed (moved-from: none).
    class Hold {
    public:
        Hold() = default;
        Hold(Hold&& other) noexcept : budget_(other.budget_), bytes_(other.bytes_) { other.budget_ = nullptr; }
        Hold& operator=(Hold&&) = delete;
        ~Hold();

    private:
        friend class MemoryBudget;
        Hold(MemoryBudget* budget, std::uint64_t bytes) : budget_(budget), bytes_(bytes) {}
        MemoryBudget* budget_ = nullptr;
        std::uint64_t bytes_ = 0;
    };
    // Waits until `bytes` fit beside what is held, then holds them. `bytes`
    // must be at most limit() (callers refuse larger analyses first).
    Hold reserve(std::uint64_t bytes);
    // The most held at once so far (tests, diagnostics).
    std::uint64_t peak() const;

private:
    void release(std::uint64_t bytes);
    const std::uint64_t limit_;
    mutable std::mutex mutex_;
    std::condition_variable freed_;
    std::uint64_t held_ = 0, peak_ = 0;
};
// The budget every analysis of this process shares unless told otherwise
// (kMaxAnalysisBytes).
MemoryBudget& shared_memory_budget();

// Where analyses are cached by default: $XDG_CACHE_HOME/depthcull/analysis, else
// ~/.cache/depthcull/analysis; empty when neither can be found.
std::string default_cache_dir();

// One analysis through the cache (cache_dir empty: no cache). *hit tells
// whether it was read from the cache. Every command analyzes through it,
// so they share one cache.
// `name` (the image file) names it in errors; the analysis' scratch memory
// is reserved from `budget` (null: shared_memory_budget()) while it runs,
// and an analysis that needs more than the whole budget is an depthcull::Error
// naming `name`, the rect and the limit, raised before anything is
// allocated.
// The depthcull::Error analyze_cached raises when an analysis of `rect` would
// need more scratch memory than the whole budget, raised here without
// analysing (callers check on an image's header before decoding it).
void check_analysis_memory(const std::string& name, Rect rect, const AnalyzeOptions& options, MemoryBudget* budget = nullptr);
ImageAnalysis analyze_cached(ImageView image, Rect rect, const AnalyzeOptions& options, const std::string& cache_dir,
                             bool* hit = nullptr, const std::string& name = "image", MemoryBudget* budget = nullptr);

// One analysis for every frame of an animation (Element::animation),
// through the cache: boundary polygons hold the union of the frames'
// non-transparent texels, opaque polygons only texels opaque in all, so
// frame 0's meshes draw any frame once the UVs move to it; polygons on
// frame 0's rect. `images` are the decoded scene images, indexed like
// Scene::images.
// `name` and `budget` as for analyze_cached.
ImageAnalysis analyze_animation(const std::vector<ImageView>& images, const Animation& animation, const AnalyzeOptions& options,
                                const std::string& cache_dir, bool* hit = nullptr, const std::string& name = "animation",
                                MemoryBudget* budget = nullptr);

struct PrepareOptions {
    io::LoadOptions load;
    // Every option of an analysis but its texture filter, which settle()
    // decides (the `filter` below, else the scene's own): analysis_options()
    // puts the settled one in.
    AnalyzeOptions analyze;
    std::string cache_dir;   // empty: no cache
    unsigned threads = 0;    // 0: all cores; output never depends on it
    // The texture filter asked for (a command line's --filter): when set it
    // wins over the scene's own (Scene::filter). Read by settle() only.
    std::optional<Filter> filter;
    // Called after each distinct (image, rect) is analyzed or read from the
    // cache, from worker threads (the callee synchronizes): progress bars.
    std::function<void(std::size_t done, std::size_t total)> progress;
    // The most bytes the decoded images may take together, checked on the
    // headers' sizes before any decode (tests pass less).
    std::uint64_t max_decoded_bytes = limits::kMaxDecodedBytes;
    // Where analyses reserve their scratch memory (null: shared_memory_budget()).
    MemoryBudget* memory = nullptr;
    // plan_target (--target) only: issue 25's stages, each on unless turned
    // off (--no-clip-hidden, --no-merge-opaque, --no-cover-plan,
    // --no-depthless), to measure what each gains.
    bool clip_hidden = true;  // hidden parts clipped where the profile says it pays
    bool merge_opaque = true; // opaque tiles laid out as in their image merged into blocks
    bool cover_plan = true;   // a second plan with OpaqueMethod::cover's pieces, kept when faster
    bool depthless = true;    // each plan also drawn without a depth buffer, kept when faster
};

// A value: copies are whole (SceneAnalysis holds indices, not pointers).
struct PreparedScene {
    Scene scene;
    // Decoded pixels: one Image per (file, colour key) that an element
    // shows, however many image entries name it (by any path or symlink);
    // images no element shows are not decoded.
    std::vector<Image> decoded;
    // index = Scene::images: its entry in `decoded`, or kNotDecoded.
    static constexpr std::size_t kNotDecoded = std::size_t(-1);
    std::vector<std::size_t> pixels;
    // The pixels of Scene::images[i]; for an image no element shows, one
    // transparent texel (renderers can upload it; nothing samples it).
    ImageView view(std::size_t image) const {
        static const std::uint8_t none[4] = {0, 0, 0, 0};
        return pixels[image] == kNotDecoded ? ImageView{none, 1, 1, 4} : decoded[pixels[image]].view();
    }
    // view(i) for every image, index = Scene::images (what renderers take).
    std::vector<ImageView> views() const {
        std::vector<ImageView> out;
        out.reserve(pixels.size());
        for (std::size_t i = 0; i < pixels.size(); ++i) out.push_back(view(i));
        return out;
    }
    SceneAnalysis analysis;    // per distinct (image file, rect), and per element
    int analyzed = 0, cache_hits = 0;
    // Every file the load read besides the images (io::LoadOptions::documents).
    std::vector<std::string> documents;
};

// Loads a scene (any io::read_scene format) and its images, settles its
// filter (settle()) and analyzes every distinct (image, rect) the elements
// use, through the cache when given. optimize() runs it as its first stage.
PreparedScene prepare_scene(const std::string& path, const PrepareOptions& options);

// ---- --target: what a cost profile chooses for a prepared scene

// Per element the analysis to reconstruct with and whether the opaque
// pass is drawn. A value: the candidates are found by index and the choice
// holds its own analyses (TargetChoice::analysis), so a copy is whole and
// outlives the original.
struct TargetPlan {
    CostProfile profile;
    std::vector<int> budgets;              // vertex budgets analyzed, ascending; the last is --max-vertices
    int min_opaque_area = 0;               // MIN_OPAQUE_AREA from the profile
    // Per distinct rect k of the prepared analysis and budget b, at
    // candidate(k, b); empty for a rect no element uses.
    std::vector<ImageAnalysis> candidates;
    const ImageAnalysis& candidate(std::size_t key, std::size_t budget) const { return candidates[key * budgets.size() + budget]; }
    // What choose_for_target chose: choice.analysis is what reconstruction takes.
    TargetChoice choice;
    int analyzed = 0, cache_hits = 0;
    // Reconstruction options with the choice applied (opaque_polygons).
    ReconstructOptions reconstruct;
    // Issue 25: the plan with OpaqueMethod::cover's pieces (up to
    // kCoverPlanPolygons per image) was predicted faster than the default's.
    bool opaque_cover = false;
};

// Analyzes each distinct image rect of `prepared` at a few vertex budgets
// (4, 6, 8 up to options.analyze's cap) with the profile's MIN_OPAQUE_AREA
// (through the cache), then choose_for_target for each plan it weighs (on
// options.threads side by side). Deterministic; never depends on
// options.threads.
TargetPlan plan_target(const PreparedScene& prepared, const PrepareOptions& options, const CostProfile& profile,
                       const ReconstructOptions& reconstruct);

// What one of plan_target's choices may hold at once, reserved from
// PrepareOptions::memory before it runs, so choices side by side on threads
// stay within the budget whatever -j is (past it they run one at a time):
// kTargetChoiceBytesPerElement per element for its contestant frames, plus
// kTargetChoiceFixedBytes for its memos (cuts and element graphs, each
// bounded) and the cost model's depth band. An estimate (a scene of 125,000
// tiles held 1.5 KiB per element per choice), not a limit: one choice runs
// even when it needs more than the whole budget.
inline constexpr std::uint64_t kTargetChoiceBytesPerElement = 2048;
inline constexpr std::uint64_t kTargetChoiceFixedBytes = std::uint64_t(128) << 20;
std::uint64_t target_choice_bytes(const Scene& scene);

// ---- optimize: the whole pipeline as one call. Every command that
// optimizes a scene (optimize, render, bench, report), the C API and the
// examples go through it; nothing else strings the stages together.

struct OptimizeOptions {
    PrepareOptions prepare;
    // The options reconstruction starts from; with a target the plan's
    // choice replaces opaque_polygons, clip_hidden and merge_opaque.
    // insertion_points given here are kept, the scene's are added below.
    ReconstructOptions reconstruct;
    // A built-in cost profile ("llvmpipe", "ipad1") or a profile file
    // (resolve_target); empty: no target planning.
    std::string target;
    // The profile when the caller resolved `target` itself (the CLI's
    // --target auto finds the GL renderer, an edge the pipeline does not
    // reach); then `target` is only named in messages.
    std::optional<CostProfile> profile;
    // The most elements planned for a target (limits::kMaxTargetElements;
    // tests pass less): past it, no plan, a warning through
    // prepare.load.warning (an Error when prepare.load.strict).
    std::size_t max_target_elements = limits::kMaxTargetElements;
    // Depth levels reserved at each of the scene's insertion points (object
    // layers, the scene JSON's, LoadOptions::insert_at); 0: none.
    std::int64_t insertion_levels = 0;
    // false: stop after the analysis and the plan, for callers that build
    // each mode's meshes themselves (render, bench, report).
    bool reconstruct_meshes = true;
    // Called before each stage: "analyzing", "choosing for --target",
    // "reconstructing" (progress lines).
    std::function<void(const char* stage)> stage;
};

// The texture filter and the target profile a run uses, decided in this
// one place. The filter: PrepareOptions::filter when given (a command
// line's --filter), else the scene's own (Scene::filter). The profile:
// OptimizeOptions::target resolved, none without one. optimize() writes
// the filter into its scene (OptimizeResult::prepared.scene.filter), where
// the analysis (analysis_options), target planning, reconstruction, the
// meshes and the renderers all read it; the profile lives in the plan.
struct Settled {
    Filter filter = Filter::nearest;
    std::optional<CostProfile> profile;
};
Settled settle(const Scene& scene, const OptimizeOptions& options);

// The options each analysis of `scene` runs with: options.analyze with the
// scene's settled filter. The one place an AnalyzeOptions gets its filter.
AnalyzeOptions analysis_options(const PrepareOptions& options, const Scene& scene);

// Wall-clock seconds of each stage, measured at this edge only: no value
// the stages return, nor any cache entry, holds a clock reading.
struct StageSeconds {
    double analysis = 0;       // load, decode, analyze (prepare_scene)
    double planning = 0;       // the target's extra budgets and the choice
    double reconstruction = 0; // reconstruct_scene
};

// Everything one optimization produced. A value: copies are whole.
struct OptimizeResult {
    // The scene (its filter the settled one), its pixels and the analysis
    // reconstruction took: with a target, the plan's choice.
    PreparedScene prepared;
    std::optional<TargetPlan> plan;   // with a target: its candidates and what it chose
    ReconstructOptions reconstruct;   // what reconstruction ran (or, without meshes, would run) with
    SceneMeshes meshes;               // empty unless reconstruct_meshes and status is ok
    // Reconstruction's verdict: a scene it refuses (invalid_scene,
    // too_many_depth_levels) is the caller's to word, as each words it.
    ReconstructStatus status = ReconstructStatus::ok;
    StageSeconds seconds;
};

// A scene already in memory with each element's analysis (the C API's
// dc_scene): nothing to load, decode or analyze, and no target (its
// pixels are not here). analysis.of(i) null: the element has none.
struct SceneSource {
    Scene scene;
    SceneAnalysis analysis;
};

// Load, settle, decode, analyze (through the cache), plan for the target
// and reconstruct. Bad input is an depthcull::Error with a one-line message naming
// the file and the place; a scene reconstruction refuses is
// OptimizeResult::status.
OptimizeResult optimize(const std::string& path, const OptimizeOptions& options);
OptimizeResult optimize(SceneSource source, const OptimizeOptions& options);

// ---- Atlases (TexturePacker JSON, multipack, cocos2d-x plist): every
// frame analyzed (through the cache, on threads), the polygons written by
// io::atlas_polygons_json / io::atlas_polygons_plist.

struct AtlasPolygonOptions {
    AnalyzeOptions analyze;
    std::string cache_dir;   // empty: no cache
    unsigned threads = 0;    // 0: all cores
    std::function<void(std::size_t done, std::size_t total)> progress; // called from worker threads
    bool plist = false; // write a cocos2d-x format 3 plist (one page only)
    MemoryBudget* memory = nullptr; // as PrepareOptions::memory
    // What the atlas reader and the page decodes assumed (io::report_warnings):
    // one line each to `warning`, in file order, or an depthcull::Error with `strict`.
    std::function<void(const std::string&)> warning;
    bool strict = false;
};
struct AtlasAnalysis {
    io::Atlas atlas;
    Image page;                        // pages[0]
    std::vector<Image> pages;          // index = Atlas::pages
    std::vector<ImageAnalysis> frames; // index = atlas.frames
    int cache_hits = 0;
};
// The atlas with polygons: JSON in the input's form, or a cocos2d-x
// format 3 plist when the input is one or options.plist (the text never
// depends on `threads`); `analysis`, when given, receives the atlas, its
// pages and each frame's analysis (for previews).
std::string atlas_with_polygons(const std::string& path, const AtlasPolygonOptions& options, io::AtlasPolygonStats* stats = nullptr,
                                AtlasAnalysis* analysis = nullptr);

} // namespace depthcull::pipeline
