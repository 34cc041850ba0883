// depthcull: the scene pipeline shared by optimize, render, bench, report
// and atlas: load (depthcull/io.h formats), decode each image once,
// analyze each distinct (image, rect) once through the on-disk cache, on
// threads; reconstruction then takes the result (depthcull/scene.h). The
// orchestration lives here so io stays formats only and the core stays
// pure. Like io, everything here may do I/O and throws io::Error only.
#pragma once

#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "depthcull/cost.h"
#include "depthcull/io.h"
#include "depthcull/scene.h"

namespace depthcull::pipeline {

// Runs fn(i) for i in [0, n) on `threads` threads (0: all cores). Callers
// store results by index, so output never depends on the thread count;
// the error of the lowest failing index is rethrown, as a serial run would.
void parallel_for(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& fn);

// Where analyses are cached by default: $XDG_CACHE_HOME/depthcull/analysis, else
// ~/.cache/depthcull/analysis; empty when neither can be found.
std::string default_cache_dir();

// One analysis through the cache (cache_dir empty: no cache). *hit tells
// whether it was read from the cache. Every command analyzes through it,
// so they share one cache.
ImageAnalysis analyze_cached(ImageView image, Rect rect, const AnalyzeOptions& options, const std::string& cache_dir,
                             bool* hit = nullptr);

// One analysis for every frame of an animation (Element::animation),
// through the cache: boundary polygons hold the union of the frames'
// non-transparent texels, opaque polygons only texels opaque in all, so
// frame 0's meshes draw any frame once the UVs move to it; polygons on
// frame 0's rect. `images` are the decoded scene images, indexed like
// Scene::images.
ImageAnalysis analyze_animation(const std::vector<Image>& images, const Animation& animation, const AnalyzeOptions& options,
                                const std::string& cache_dir, bool* hit = nullptr);

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
};

// A value: copies are whole (SceneAnalysis holds indices, not pointers).
struct PreparedScene {
    Scene scene;
    std::vector<Image> images; // decoded, index = Scene::images (entries naming one file share pixels)
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
    SceneAnalysis analysis;                // choice.element_analysis as a value
    int analyzed = 0, cache_hits = 0;
    // Reconstruction options with the choice applied (opaque_polygons).
    ReconstructOptions reconstruct;
};

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
