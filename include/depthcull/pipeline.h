// depthcull: the scene pipeline shared by optimize, render, bench, report
// and atlas: load (depthcull/io.h formats), decode each image once,
// analyze each distinct (image, rect) once through the on-disk cache, on
// threads; reconstruction then takes the result (depthcull/scene.h). The
// orchestration lives here so io stays formats only and the core stays
// pure. Like io, everything here may do I/O and throws io::Error only.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

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
    double analysis_seconds = 0;
};

// Loads a scene (any io::load_scene format) and its images, and analyzes
// every distinct (image, rect) the elements use, through the cache when given.
PreparedScene prepare_scene(const std::string& path, const PrepareOptions& options);

// ---- TexturePacker atlases: every frame analyzed (through the cache, on
// threads), the polygons written by io::atlas_polygons_json.

struct AtlasPolygonOptions {
    AnalyzeOptions analyze;
    std::string cache_dir;   // empty: no cache
    unsigned threads = 0;    // 0: all cores
    std::function<void(std::size_t done, std::size_t total)> progress; // called from worker threads
};
struct AtlasAnalysis {
    io::Atlas atlas;
    Image page;
    std::vector<ImageAnalysis> frames; // index = atlas.frames
    int cache_hits = 0;
};
// The atlas JSON with polygons (the text never depends on `threads`);
// `analysis`, when given, receives the atlas, its page and each frame's
// analysis (for previews).
std::string atlas_with_polygons(const std::string& path, const AtlasPolygonOptions& options, io::AtlasPolygonStats* stats = nullptr,
                                AtlasAnalysis* analysis = nullptr);

} // namespace depthcull::pipeline
