// pipeline::prepare_scene: the pipeline shared by optimize, render and bench.
// Loads the scene, reads and decodes each image file once, and analyzes each distinct
// (image file, rect) once, on threads, through the cache when one is set.
// Work is split by index and results stored by index, so the output never
// depends on the thread count or timing.
#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <thread>
#include <tuple>

#include <filesystem>

#include <sys/stat.h>

#include "depthcull/limits.h"
#include "depthcull/pipeline.h"
#include "pipeline/cache.h"
#include "pipeline/parallel.h"
#include "pipeline/stages.h"

namespace depthcull::pipeline {

using depthcull::Error;

std::string default_cache_dir() { return user_cache_dir("analysis"); }

MemoryBudget::Hold::~Hold() {
    if (budget_) budget_->release(bytes_);
}

MemoryBudget::Hold MemoryBudget::reserve(std::uint64_t bytes) {
    bytes = std::min(bytes, limit_); // more would wait for ever; callers refuse it first
    std::unique_lock lock(mutex_);
    freed_.wait(lock, [&] { return held_ + bytes <= limit_; });
    held_ += bytes;
    peak_ = std::max(peak_, held_);
    return Hold(this, bytes);
}

void MemoryBudget::release(std::uint64_t bytes) {
    {
        std::lock_guard lock(mutex_);
        held_ -= bytes;
    }
    freed_.notify_all();
}

std::uint64_t MemoryBudget::peak() const {
    std::lock_guard lock(mutex_);
    return peak_;
}

MemoryBudget& shared_memory_budget() {
    static MemoryBudget budget(kMaxAnalysisBytes);
    return budget;
}

namespace {

std::string mib_text(std::uint64_t bytes) { return std::to_string((bytes + (std::uint64_t(1) << 20) - 1) >> 20) + " MiB"; }

// The core's analysis within the budget: refused up front when it would
// need more than the whole budget, else run once its bytes are reserved.
std::string rect_name(const std::string& name, Rect rect) {
    return name + ": rect " + std::to_string(rect.x) + "," + std::to_string(rect.y) + " " + std::to_string(rect.w) + "x" + std::to_string(rect.h);
}

std::string limit_text(const MemoryBudget& budget) { return "the limit of " + mib_text(budget.limit()) + " (kMaxAnalysisBytes)"; }

ImageAnalysis analyze_within(ImageView image, Rect rect, const AnalyzeOptions& options, const std::string& name, MemoryBudget& budget) {
    check_analysis_memory(name, rect, options, &budget);
    const std::uint64_t need = analysis_scratch_bytes(rect, options);
    const std::string where = rect_name(name, rect), limit = limit_text(budget);
    MemoryBudget::Hold hold = budget.reserve(need);
    ImageAnalysis out;
    switch (analyze_image(image, rect, options, budget.limit(), out)) {
    case AnalyzeStatus::ok: break;
    case AnalyzeStatus::over_memory_limit: // checked above; kept for completeness
        throw depthcull::Error(where + ": analysing it needs about " + mib_text(need) + " of memory, over " + limit);
    case AnalyzeStatus::out_of_memory:
        throw depthcull::Error(where + ": out of memory analysing it (about " + mib_text(need) + ", within " + limit +
                        "; fewer threads, -j, need less at once)");
    }
    return out;
}

} // namespace

void check_analysis_memory(const std::string& name, Rect rect, const AnalyzeOptions& options, MemoryBudget* budget) {
    const MemoryBudget& memory = budget ? *budget : shared_memory_budget();
    const std::uint64_t need = analysis_scratch_bytes(rect, options);
    if (need > memory.limit())
        throw depthcull::Error(rect_name(name, rect) + ": analysing it needs about " + mib_text(need) + " of memory, over " + limit_text(memory));
}

ImageAnalysis analyze_cached(ImageView image, Rect rect, const AnalyzeOptions& options, const std::string& cache_dir, bool* hit,
                             const std::string& name, MemoryBudget* budget) {
    MemoryBudget& memory = budget ? *budget : shared_memory_budget();
    if (hit) *hit = false;
    if (cache_dir.empty()) return analyze_within(image, rect, options, name, memory);
    const pipeline::CacheKey key = pipeline::analysis_key(image, rect, options);
    if (auto cached = pipeline::cache_load(cache_dir, key, rect)) {
        if (hit) *hit = true;
        cached->bleeding_edges = edges_bleed(image, rect); // not cached (ImageAnalysis::bleeding_edges)
        return std::move(*cached);
    }
    ImageAnalysis analysis = analyze_within(image, rect, options, name, memory);
    pipeline::cache_store(cache_dir, key, analysis);
    return analysis;
}

namespace {

// Which file a path names: its device and inode, so that two spellings or
// a symlink share one decode; the path itself when it cannot be stat'ed
// (the decode then reports why).
std::string file_identity(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) == 0) return "\n" + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
    return path;
}

std::string mib(std::uint64_t bytes) { return std::to_string((bytes + (std::uint64_t(1) << 20) - 1) >> 20) + " MiB"; }

std::string image_name(const std::string& path, const SceneImage& img, std::size_t i) {
    return path + ": image " + std::to_string(i) + " \"" + img.id + "\" (" + (img.has_fill ? "fill " + io::color_key_text(img.fill) : img.path) + ")";
}

// Step 1: animations are checked on their frames' rects, before any pixel
// is decoded: each frame is read once per texel to combine them.
void check_animations(const std::string& path, const Scene& scene) {
    for (std::size_t a = 0; a < scene.animations.size(); ++a) {
        const Animation& animation = scene.animations[a];
        if (animation.frames.empty()) continue;
        const AnimationFrame& first = animation.frames.front();
        const std::string where = image_name(path, scene.images[std::size_t(first.image)], std::size_t(first.image)) + ": animation " +
                                  std::to_string(a) + " at " + std::to_string(first.rect.x) + "," + std::to_string(first.rect.y);
        if (animation.frames.size() > limits::kMaxAnimationFrames)
            throw Error(where + ": " + std::to_string(animation.frames.size()) + " frames, more than " +
                        std::to_string(limits::kMaxAnimationFrames) + " (kMaxAnimationFrames)");
        const std::uint64_t texels = std::uint64_t(animation.frames.size()) * std::uint64_t(std::max(first.rect.w, 0)) *
                                     std::uint64_t(std::max(first.rect.h, 0));
        if (texels > limits::kMaxAnimationTexels)
            throw Error(where + ": " + std::to_string(animation.frames.size()) + " frames of " + std::to_string(first.rect.w) + "x" +
                        std::to_string(first.rect.h) + " are " + std::to_string(texels) + " texels, more than " +
                        std::to_string(limits::kMaxAnimationTexels) + " (kMaxAnimationTexels)");
    }
}

// Step 2: which images are decoded, into out.pixels (each image's decode)
// and the image index of each decode, returned; the decoded total checked
// against the limit.
std::vector<std::size_t> plan_decodes(const std::string& path, const Scene& scene, const PrepareOptions& options, PreparedScene& out) {
    // Only images an element shows are decoded (an animated element shows
    // all its frames' images), each (file, colour key) once: entries naming
    // one file, by any path or symlink, with one key share its pixels.
    std::vector<std::uint8_t> shown(scene.images.size(), 0);
    for (const Element& e : scene.elements) {
        shown[std::size_t(e.image)] = 1;
        if (e.animation >= 0)
            for (const AnimationFrame& f : scene.animations[std::size_t(e.animation)].frames) shown[std::size_t(f.image)] = 1;
    }
    std::map<std::string, std::size_t> decode_of_key;
    out.pixels.assign(scene.images.size(), PreparedScene::kNotDecoded);
    std::vector<std::size_t> to_decode; // image index of each decode
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < scene.images.size(); ++i) {
        if (!shown[i]) continue;
        const SceneImage& img = scene.images[i];
        auto [it, fresh] = decode_of_key.emplace(img.has_fill ? "\nfill " + io::color_key_text(img.fill)
                                                              : file_identity(img.path) + (img.has_trans ? "\n" + io::color_key_text(img.trans) : std::string()),
                                                 to_decode.size());
        out.pixels[i] = it->second;
        if (!fresh) continue;
        to_decode.push_back(i);
        // Sizes are the headers' (the loaders read them): the total is
        // known before the first decode allocates.
        const std::uint64_t bytes = std::uint64_t(std::max(img.width, 0)) * std::uint64_t(std::max(img.height, 0)) * 4;
        total += bytes;
        if (total > options.max_decoded_bytes)
            throw Error(image_name(path, img, i) + ": " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                        " brings the decoded images to " + mib(total) + ", over the limit of " + mib(options.max_decoded_bytes) +
                        " (kMaxDecodedBytes)");
    }
    return to_decode;
}

// Step 3: the decodes, into out.decoded, from the bytes the loaders kept.
void decode_images(const std::string& path, const Scene& scene, const PrepareOptions& options, const std::vector<std::size_t>& to_decode,
                   io::ImageFiles& files, PreparedScene& out) {
    out.decoded.resize(to_decode.size());
    // Decode warnings (a CMYK JPEG, an animated WebP) per image, reported
    // after the decodes in image order: the same lines for any thread count.
    std::vector<std::vector<std::string>> warnings(to_decode.size());
    parallel_for(to_decode.size(), options.threads, [&](std::size_t k) {
        std::size_t i = to_decode[k];
        const SceneImage& img = scene.images[i];
        out.decoded[k] = io::read_scene_image(img, &files, &warnings[k]);
        if (options.load.strict && !warnings[k].empty()) io::report_warnings(warnings[k], options.load);
        if (out.decoded[k].width != img.width || out.decoded[k].height != img.height)
            throw Error(path + ": image " + std::to_string(i) + " \"" + img.id + "\": " + img.path + " is " +
                        std::to_string(out.decoded[k].width) + "x" + std::to_string(out.decoded[k].height) + ", expected " +
                        std::to_string(img.width) + "x" + std::to_string(img.height));
    });
    for (const std::vector<std::string>& lines : warnings) io::report_warnings(lines, options.load);
}

// What is analysed: each distinct (decode, rect), or animation, once.
struct AnalysisWork {
    std::vector<std::pair<std::size_t, Rect>> items; // (decode, rect)
    std::vector<int> animation;                      // per item: the animation analysed, or -1
    std::vector<std::size_t> of_element;             // per element: its item
};

// Step 4: distinct (file, rect) in order of first use: deterministic
// indices. An animated element's analysis is its animation's (all frames).
AnalysisWork distinct_work(const Scene& scene, const PreparedScene& out) {
    std::map<std::tuple<std::size_t, int, int, int, int>, std::size_t> distinct;
    AnalysisWork work;
    work.of_element.resize(scene.elements.size());
    for (std::size_t i = 0; i < scene.elements.size(); ++i) {
        const Element& e = scene.elements[i];
        std::size_t file = out.pixels[std::size_t(e.image)];
        auto key = e.animation >= 0 ? std::make_tuple(SIZE_MAX, e.animation, 0, 0, 0) : std::make_tuple(file, e.rect.x, e.rect.y, e.rect.w, e.rect.h);
        auto [it, fresh] = distinct.emplace(key, work.items.size());
        if (fresh) {
            work.items.push_back({file, e.rect});
            work.animation.push_back(e.animation);
        }
        work.of_element[i] = it->second;
    }
    return work;
}

// Step 5: each item analysed (through the cache), into out.analysis, with
// the cache's hits counted.
void analyze_work(const std::string& path, const Scene& scene, const AnalyzeOptions& analyze, const PrepareOptions& options,
                  const std::vector<std::size_t>& to_decode, const AnalysisWork& work, PreparedScene& out) {
    const std::vector<ImageView> views = out.views();
    std::vector<ImageAnalysis>& analyses = out.analysis.images;
    analyses.resize(work.items.size());
    std::vector<std::uint8_t> hit(work.items.size(), 0);
    std::atomic<std::size_t> done{0};
    parallel_for(work.items.size(), options.threads, [&](std::size_t k) {
        bool from_cache = false;
        if (work.animation[k] >= 0) {
            const Animation& animation = scene.animations[std::size_t(work.animation[k])];
            const std::size_t image = std::size_t(animation.frames.front().image);
            analyses[k] = analyze_animation(views, animation, analyze, options.cache_dir, &from_cache,
                                            image_name(path, scene.images[image], image) + ": animation " + std::to_string(work.animation[k]),
                                            options.memory);
        } else {
            const std::size_t image = to_decode[work.items[k].first];
            analyses[k] = analyze_cached(out.decoded[work.items[k].first].view(), work.items[k].second, analyze, options.cache_dir, &from_cache,
                                         image_name(path, scene.images[image], image), options.memory);
        }
        hit[k] = from_cache;
        if (options.progress) options.progress(++done, work.items.size());
    });
    out.analysis.of_element.resize(scene.elements.size());
    for (std::size_t i = 0; i < scene.elements.size(); ++i) out.analysis.of_element[i] = std::uint32_t(work.of_element[i]);
    for (std::uint8_t h : hit) out.cache_hits += h;
    out.analyzed = int(work.items.size()) - out.cache_hits;
}

} // namespace

PreparedScene prepare_settled(const std::string& path, const OptimizeOptions& settings, Settled* settled) {
    const PrepareOptions& options = settings.prepare;
    PreparedScene out;
    // The loaders read each image file whole for its size and keep it here;
    // the decode below reads these bytes: each file is opened once.
    io::ImageFiles files;
    io::LoadOptions load = options.load;
    load.image_files = &files;
    load.documents = &out.documents;
    out.scene = io::read_scene(path, load);
    Scene& scene = out.scene;

    // Settled once, before any pixel is decoded: a bad --target file fails
    // before the work. From here on the scene's filter is the one in force.
    Settled decided = settle(scene, settings);
    scene.filter = decided.filter;
    if (settled) *settled = std::move(decided);
    const AnalyzeOptions analyze = analysis_options(options, scene);

    check_animations(path, scene);
    const std::vector<std::size_t> to_decode = plan_decodes(path, scene, options, out);
    decode_images(path, scene, options, to_decode, files, out);
    files.clear(); // decoded: the compressed bytes are not needed again
    analyze_work(path, scene, analyze, options, to_decode, distinct_work(scene, out), out);
    return out;
}

PreparedScene prepare_scene(const std::string& path, const PrepareOptions& options) {
    OptimizeOptions settings;
    settings.prepare = options;
    // std::bad_alloc from a scene that fits the limits but not this machine.
    return io::guarded(path, [&] { return prepare_settled(path, settings, nullptr); });
}

} // namespace depthcull::pipeline
