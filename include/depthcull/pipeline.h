// depthcull: the scene pipeline shared by optimize, render, bench, report
// and atlas: load (depthcull/io.h formats), decode each image once,
// analyze each distinct (image, rect) once through the on-disk cache, on
// threads; reconstruction then takes the result (depthcull/scene.h). The
// orchestration lives here so io stays formats only and the core stays
// pure. Like io, everything here may do I/O and throws io::Error only.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "depthcull/cost.h"
#include "depthcull/io.h"
#include "depthcull/scene.h"

namespace depthcull::pipeline {

// Runs fn(i) for i in [0, n) on `threads` threads (0: all cores; at most
// limits::kMaxThreads), the calling thread one of them. Threads the system
// refuses to start are not an error: those running do their share. Callers
// store results by index, so output never depends on the thread count;
// the error of the lowest failing index is rethrown, as a serial run would.
void parallel_for(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& fn);

// Scratch memory that analyses running at once may hold together
// (analysis_scratch_bytes each): a worker reserves an analysis's estimate
// before it runs and waits while the others' reservations leave too little,
// so peak memory stays within the budget whatever -j is (at -j 8, eight
// 4096^2 frames would otherwise need 4 GiB at once). Results are stored by
// index, so waiting never changes the output. The budget is also the most
// one analysis may need: a larger one is refused (io::Error naming the
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
// and an analysis that needs more than the whole budget is an io::Error
// naming `name`, the rect and the limit, raised before anything is
// allocated.
// The io::Error analyze_cached raises when an analysis of `rect` would
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
    AnalyzeOptions analyze;  // analyze.filter is not read: see filter_override
    std::string cache_dir;   // empty: no cache
    unsigned threads = 0;    // 0: all cores; output never depends on it
    // The texture filter, and who wins: this override when set (a command
    // line's --filter), else the scene's own (Scene::filter). prepare_scene
    // writes the winner into PreparedScene::scene.filter, analyzes for it
    // and reconstruction then reads it there: one value from file to meshes.
    std::optional<Filter> filter_override;
    // Called after each distinct (image, rect) is analyzed or read from the
    // cache, from worker threads (the callee synchronizes): progress bars.
    std::function<void(std::size_t done, std::size_t total)> progress;
    // The most bytes the decoded images may take together, checked on the
    // headers' sizes before any decode (tests pass less).
    std::uint64_t max_decoded_bytes = limits::kMaxDecodedBytes;
    // Where analyses reserve their scratch memory (null: shared_memory_budget()).
    MemoryBudget* memory = nullptr;
    // plan_target (--target) only: issue 25's stages, each on unless turned
    // off (--no-clip-hidden, --no-merge-opaque, --no-cover-plan), to measure
    // what each gains.
    bool clip_hidden = true;  // hidden parts clipped where the profile says it pays
    bool merge_opaque = true; // opaque tiles laid out as in their image merged into blocks
    bool cover_plan = true;   // a second plan with OpaqueMethod::cover's pieces, kept when faster
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
};

// Loads a scene (any io::load_scene format) and its images, and analyzes
// every distinct (image, rect) the elements use, through the cache when given.
PreparedScene prepare_scene(const std::string& path, const PrepareOptions& options);

// ---- --target: what a cost profile chooses for a prepared scene

// Per element the analysis to reconstruct with and whether the opaque
// pass is drawn. `analysis` is a value (a copy of the chosen candidates):
// put it in PreparedScene::analysis to reconstruct with the choice.
struct TargetPlan {
    CostProfile profile;
    std::vector<int> budgets;              // vertex budgets analyzed, ascending; the last is --max-vertices
    int min_opaque_area = 0;               // MIN_OPAQUE_AREA from the profile
    std::deque<ImageAnalysis> candidates;  // per distinct rect and budget (choice's pointers point here)
    TargetChoice choice;
    SceneAnalysis analysis;                // choice.analysis (a copy)
    int analyzed = 0, cache_hits = 0;
    // Reconstruction options with the choice applied (opaque_polygons).
    ReconstructOptions reconstruct;
    // Issue 25: the plan with OpaqueMethod::cover's pieces (up to
    // kCoverPlanPolygons per image) was predicted faster than the default's.
    bool opaque_cover = false;
};

// Most opaque pieces per image rect plan_target's cover plan analyzes.
inline constexpr int kCoverPlanPolygons = 64;

// Analyzes each distinct image rect of `prepared` at a few vertex budgets
// (4, 6, 8 up to options.analyze's cap) with the profile's MIN_OPAQUE_AREA
// (through the cache), then choose_for_target. Deterministic; never
// depends on options.threads.
TargetPlan plan_target(const PreparedScene& prepared, const PrepareOptions& options, const CostProfile& profile,
                       const ReconstructOptions& reconstruct);

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
    // one line each to `warning`, in file order, or an io::Error with `strict`.
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
