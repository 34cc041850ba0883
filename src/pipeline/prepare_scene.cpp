// pipeline::prepare_scene: the pipeline shared by optimize, render and bench.
// Loads the scene, reads and decodes each image file once, and analyzes each distinct
// (image file, rect) once, on threads, through the cache when one is set.
// Work is split by index and results stored by index, so the output never
// depends on the thread count or timing.
#include <atomic>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#include <tuple>

#include <filesystem>

#include "depthcull/pipeline.h"
#include "io/cache.h"
#include "io/formats.h"

namespace depthcull::pipeline {

using io::Error;

void parallel_for(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& fn) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    threads = unsigned(std::min<std::size_t>(threads, n));
    if (threads <= 1) {
        for (std::size_t i = 0; i < n; ++i) fn(i);
        return;
    }
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    std::exception_ptr error;
    std::size_t error_index = n;
    std::mutex error_mutex;
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) {
        pool.emplace_back([&] {
            for (std::size_t i; !failed && (i = next.fetch_add(1)) < n;) {
                try {
                    fn(i);
                } catch (...) {
                    // Keep the lowest index's error, as a serial run reports.
                    std::lock_guard lock(error_mutex);
                    if (i < error_index) {
                        error_index = i;
                        error = std::current_exception();
                    }
                    failed = true;
                }
            }
        });
    }
    for (auto& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

std::string default_cache_dir() {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return (std::filesystem::path(xdg) / "depthcull" / "analysis").string();
    if (const char* home = std::getenv("HOME"); home && *home)
        return (std::filesystem::path(home) / ".cache" / "depthcull" / "analysis").string();
    return {};
}

ImageAnalysis analyze_cached(ImageView image, Rect rect, const AnalyzeOptions& options, const std::string& cache_dir, bool* hit) {
    if (hit) *hit = false;
    if (cache_dir.empty()) return analyze_image(image, rect, options);
    const io::CacheKey key = io::analysis_key(image, rect, options);
    if (auto cached = io::cache_load(cache_dir, key, rect)) {
        if (hit) *hit = true;
        cached->bleeding_edges = edges_bleed(image, rect); // not cached (ImageAnalysis::bleeding_edges)
        return std::move(*cached);
    }
    ImageAnalysis analysis = analyze_image(image, rect, options);
    io::cache_store(cache_dir, key, analysis);
    return analysis;
}

namespace {

PreparedScene prepare(const std::string& path, const PrepareOptions& options) {
    PreparedScene out;
    // The loaders read each image file whole for its size and keep it here;
    // the decode below reads these bytes: each file is opened once.
    io::ImageFiles files;
    io::LoadOptions load = options.load;
    load.image_files = &files;
    out.scene = io::load_scene(path, load);
    Scene& scene = out.scene;

    if (options.filter_override) scene.filter = *options.filter_override;
    AnalyzeOptions analyze = options.analyze;
    analyze.filter = scene.filter;

    // Decode each (file, colour key) once; image entries naming the same
    // file with the same key share it.
    std::map<std::string, std::size_t> first_with_path;
    std::vector<std::size_t> canon(scene.images.size());
    std::vector<std::size_t> to_decode;
    for (std::size_t i = 0; i < scene.images.size(); ++i) {
        const SceneImage& img = scene.images[i];
        auto [it, fresh] = first_with_path.emplace(img.has_fill ? "\nfill " + io::colour_key_text(img.fill)
                                                                : img.path + (img.has_trans ? "\n" + io::colour_key_text(img.trans) : std::string()),
                                                   i);
        canon[i] = it->second;
        if (fresh) to_decode.push_back(i);
    }
    out.images.resize(scene.images.size());
    parallel_for(to_decode.size(), options.threads, [&](std::size_t k) {
        std::size_t i = to_decode[k];
        const SceneImage& img = scene.images[i];
        out.images[i] = io::load_scene_image(img, &files);
        if (out.images[i].width != img.width || out.images[i].height != img.height)
            throw Error(path + ": image " + std::to_string(i) + " \"" + img.id + "\": " + img.path + " is " +
                        std::to_string(out.images[i].width) + "x" + std::to_string(out.images[i].height) + ", expected " +
                        std::to_string(img.width) + "x" + std::to_string(img.height));
    });
    files.clear(); // decoded: the compressed bytes are not needed again
    for (std::size_t i = 0; i < scene.images.size(); ++i)
        if (canon[i] != i) out.images[i] = out.images[canon[i]];

    // Distinct (file, rect) in order of first use: deterministic indices.
    // An animated element's analysis is its animation's (all frames).
    std::map<std::tuple<std::size_t, int, int, int, int>, std::size_t> distinct;
    std::vector<std::size_t> element_slot(scene.elements.size());
    std::vector<std::pair<std::size_t, Rect>> work;
    std::vector<int> work_animation;
    for (std::size_t i = 0; i < scene.elements.size(); ++i) {
        const Element& e = scene.elements[i];
        std::size_t file = canon[std::size_t(e.image)];
        auto key = e.animation >= 0 ? std::make_tuple(SIZE_MAX, e.animation, 0, 0, 0) : std::make_tuple(file, e.rect.x, e.rect.y, e.rect.w, e.rect.h);
        auto [it, fresh] = distinct.emplace(key, work.size());
        if (fresh) {
            work.push_back({file, e.rect});
            work_animation.push_back(e.animation);
        }
        element_slot[i] = it->second;
    }
    std::vector<ImageAnalysis>& analyses = out.analysis.images;
    analyses.resize(work.size());
    std::vector<std::uint8_t> hit(work.size(), 0);
    std::atomic<std::size_t> done{0};
    parallel_for(work.size(), options.threads, [&](std::size_t k) {
        bool from_cache = false;
        if (work_animation[k] >= 0)
            analyses[k] = analyze_animation(out.images, scene.animations[std::size_t(work_animation[k])], analyze, options.cache_dir, &from_cache);
        else
            analyses[k] = analyze_cached(out.images[work[k].first].view(), work[k].second, analyze, options.cache_dir, &from_cache);
        hit[k] = from_cache;
        if (options.progress) options.progress(++done, work.size());
    });
    out.analysis.of_element.resize(scene.elements.size());
    for (std::size_t i = 0; i < scene.elements.size(); ++i) out.analysis.of_element[i] = std::uint32_t(element_slot[i]);
    for (std::uint8_t h : hit) out.cache_hits += h;
    out.analyzed = int(work.size()) - out.cache_hits;
    return out;
}

} // namespace

PreparedScene prepare_scene(const std::string& path, const PrepareOptions& options) {
    // std::bad_alloc from a scene that fits the limits but not this machine.
    return io::guarded(path, [&] { return prepare(path, options); });
}

} // namespace depthcull::pipeline
