// depthcull's WebAssembly entry points (issue 24): the pure core built with
// clang --target=wasm32-wasi, called from web/src/*.js.
//
// Why not the C API of include/depthcull/depthcull.h: it catches exceptions
// at its boundary and pulls in depthcull_io (files, PNG, JSON), and this
// toolchain has neither exceptions (__cxa_throw does not link) nor a file
// system worth the name. The core needs neither, so this layer is thin:
//   - every call returns a status (DCW_OK = 0) and leaves a one-line message
//     for dcw_last_error, worded as the CLI words the same error;
//   - results go into one flat buffer of doubles (dcw_result, dcw_result_size)
//     that JavaScript reads straight out of linear memory;
//   - numbers arrive as doubles and are checked here, so a fractional,
//     infinite or NaN option from JavaScript is an error, not a silent
//     truncation to int, and the checks live in one place.
// Running out of memory traps (operator new aborts without exceptions); the
// JavaScript side turns the trap into an error and makes a fresh instance.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <tuple>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "depthcull/analyze.h"
#include "depthcull/cost.h"
#include "depthcull/frame.h"
#include "depthcull/scene.h"
#include "depthcull/image.h"
#include "depthcull/limits.h"

#define DCW_EXPORT(name) __attribute__((export_name(#name)))

namespace {

using namespace depthcull;

enum Status : int { DCW_OK = 0, DCW_ERROR_INVALID_ARGUMENT = 1 };

std::string g_error;
std::vector<double> g_result;

int fail(std::string message) {
    g_error = std::move(message);
    return DCW_ERROR_INVALID_ARGUMENT;
}

// %.17g would print 0.75 as 0.75 but 0.1 as 0.10000000000000001; the
// shortest form that reads back the same is what a user typed.
std::string number_text(double v) {
    if (std::isnan(v)) return "NaN"; // as JavaScript prints them
    if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
    char buf[32];
    if (v == std::floor(v) && std::fabs(v) < 1e15) {
        std::snprintf(buf, sizeof buf, "%.0f", v); // 20000, not 2e+04
        return buf;
    }
    for (int precision = 1; precision <= 17; ++precision) {
        std::snprintf(buf, sizeof buf, "%.*g", precision, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

// The CLI's (CLI11's) wording: "--max-vertices: Value 2 not in range 4 to
// 1000", with the JavaScript option's name.
bool int_option(const char* name, double v, int lo, int hi, int* out, std::string* error) {
    if (!std::isfinite(v) || v != std::floor(v)) {
        *error = std::string(name) + ": Value " + number_text(v) + " is not an integer";
        return false;
    }
    if (v < lo || v > hi) {
        *error = std::string(name) + ": Value " + number_text(v) + " not in range " + std::to_string(lo) + " to " + std::to_string(hi);
        return false;
    }
    *out = int(v);
    return true;
}

void append_polygons(const std::vector<Polygon>& polygons) {
    g_result.push_back(double(polygons.size()));
    for (const Polygon& p : polygons) {
        g_result.push_back(double(p.size()));
        for (const Vec2& v : p) {
            g_result.push_back(v.x);
            g_result.push_back(v.y);
        }
    }
}

// dcw_analyze's arguments checked and the analysis run: false (and
// g_error set) on bad arguments.
bool analyze_args(const std::uint8_t* rgba, double width, double height, double rx, double ry, double rw, double rh,
                  double max_vertices, double split, double filter, double opaque_method, double max_opaque, double min_coverage,
                  double min_opaque_area, const char* name, ImageAnalysis* out, Rect* rect_out = nullptr) {
    const std::string who = name && *name ? std::string(name) : std::string("image");
    std::string error;
    int w = 0, h = 0;
    if (!int_option("width", width, 1, kMaxImageSide, &w, &error) || !int_option("height", height, 1, kMaxImageSide, &h, &error))
        return fail(who + ": " + error), false;
    if (std::int64_t(w) * h > kMaxImageTexels)
        return fail(who + ": " + std::to_string(w) + "x" + std::to_string(h) + " image exceeds " +
                    std::to_string(kMaxImageTexels) + " texels"), false;
    if (!rgba) return fail(who + ": no pixels"), false;
    Rect rect;
    if (!int_option("rect.x", rx, -kMaxImageSide, kMaxImageSide, &rect.x, &error) ||
        !int_option("rect.y", ry, -kMaxImageSide, kMaxImageSide, &rect.y, &error) ||
        !int_option("rect.width", rw, 0, kMaxImageSide, &rect.w, &error) ||
        !int_option("rect.height", rh, 0, kMaxImageSide, &rect.h, &error))
        return fail(who + ": " + error), false;
    const ImageView image{rgba, w, h, std::ptrdiff_t(w) * 4};
    if (rect.empty() || !image.contains(rect))
        return fail(who + ": rectangle " + std::to_string(rect.x) + "," + std::to_string(rect.y) + "," + std::to_string(rect.w) +
                    "," + std::to_string(rect.h) + " is outside the " + std::to_string(w) + "x" + std::to_string(h) + " image"), false;

    AnalyzeOptions options;
    int split_flag = 1, filter_value = 0, method = 1;
    if (!int_option("maxVertices", max_vertices, 4, 1000, &options.boundary.max_vertices, &error) ||
        !int_option("split", split, 0, 1, &split_flag, &error) || !int_option("filter", filter, 0, 1, &filter_value, &error) ||
        !int_option("opaque", opaque_method, 0, 2, &method, &error) ||
        !int_option("maxOpaque", max_opaque, 0, 64, &options.opaque.max_polygons, &error) ||
        !int_option("minOpaqueArea", min_opaque_area, 1, 1 << 30, &options.opaque.min_area, &error))
        return fail(error), false;
    if (!std::isfinite(min_coverage) || min_coverage < 0 || min_coverage > 1)
        return fail("minCoverage: Value " + number_text(min_coverage) + " not in range 0 to 1"), false;
    options.opaque.min_coverage = min_coverage;
    options.boundary.split_parts = split_flag != 0;
    options.filter = filter_value ? Filter::linear : Filter::nearest;
    options.opaque.method = method == 0 ? OpaqueMethod::paper : method == 2 ? OpaqueMethod::grow : OpaqueMethod::fast;

    *out = analyze_image(image, rect, options);
    if (rect_out) *rect_out = rect;
    return true;
}

// ---- Moving sprites (include/depthcull/frame.h's FrameAssembler) ----
//
// A handle per assembler. After warm-up a frame allocates nothing: the
// sprite input, the sprite lists, the AssembledFrame and the flat draw and
// point tables keep their capacity, and JavaScript reads the frame through
// typed-array views of linear memory (dcw_frame_info's pointers).

// Sprite input, kSpriteDoubles doubles each: image, animation, frame,
// transform a b c d e f, colour r g b a, blend (0 alpha, 1 add, 2 multiply,
// 3 opaque).
constexpr std::size_t kSpriteDoubles = 14;

// What dcw_frame_info points at, 32-bit words (wasm32 pointers): vertices
// pointer and float count, indices pointer and count, draws pointer and
// count (5 words each: image, pass 0 opaque / 1 blend, blend, first index,
// index count), opaque draw count, points pointer and count (3 words each:
// static draw, first draw, end draw), depth test, then the stats sprites,
// draw calls, opaque draws, triangles, blend batches, over budget.
constexpr std::size_t kInfoWords = 16;

struct Frames {
    FrameAssembler assembler;
    AssembledFrame frame;
    SceneMeshes points;     // only insertion_points, depth_denominator and depth_test
    bool has_points = false;
    std::vector<double> input; // per-point sprite counts, then the sprites
    std::vector<Sprite> sprites;
    std::vector<std::span<const Sprite>> lists;
    std::vector<std::uint32_t> draws, frame_points;
    std::uint32_t info[kInfoWords] = {};
    explicit Frames(const AssemblerOptions& o) : assembler(o) {}
};

// Live objects by handle (index + 1). A freed slot is reused: a table that
// only grew would keep a slot per call for good (a page making and freeing
// an assembler per frame, or failing reconstructions, would grow the
// instance's memory without bound).
template <class T> struct Handles {
    std::vector<std::unique_ptr<T>> slots;
    std::vector<std::size_t> unused; // indices of freed slots

    std::size_t add(std::unique_ptr<T> object) {
        if (unused.empty()) {
            slots.push_back(std::move(object));
            return slots.size();
        }
        const std::size_t i = unused.back();
        unused.pop_back();
        slots[i] = std::move(object);
        return i + 1;
    }
    T* get(double handle) const {
        if (!(handle >= 1 && handle <= double(slots.size())) || handle != std::floor(handle)) return nullptr;
        return slots[std::size_t(handle) - 1].get();
    }
    void free(double handle) {
        if (!get(handle)) return;
        slots[std::size_t(handle) - 1].reset();
        unused.push_back(std::size_t(handle) - 1);
    }
};

Handles<Frames> g_frames;

Frames* frames_of(double handle) {
    Frames* f = g_frames.get(handle);
    if (!f) fail("frame assembler: handle " + number_text(handle) + " is not a live assembler");
    return f;
}

const char* frame_status_text(FrameStatus s) {
    switch (s) {
    case FrameStatus::ok: return "ok";
    case FrameStatus::bad_image: return "bad image (empty rect, rect outside the texture, or a negative texture)";
    case FrameStatus::bad_sprite: return "a sprite names an unknown image or animation, or has a non-finite transform or colour";
    case FrameStatus::too_many_sprites: return "more sprites than depth levels (kMaxDepthLevels, or an insertion point's reserved levels)";
    case FrameStatus::bad_meshes: return "the static meshes have fewer insertion points than the sprite lists";
    }
    return "unknown status";
}

// Scene sizes the wasm takes (its memory is at most 4 GiB).
constexpr std::size_t kMaxSceneImagesWasm = 1 << 16;
constexpr std::size_t kMaxSceneElementsWasm = 1 << 22;

// ---- Reconstruction (paper 2.3) and --target in the wasm ----
//
// A scene built image by image and element by element from JavaScript
// (pixels copied in, as the CLI decodes its files: colour keys applied,
// fills made), then reconstructed as `depthcull optimize` does
// (pipeline::prepare_scene, plan_target): each distinct (decoded image,
// rect) analysed once, an animated element's analysis made of all its
// frames; with a target, each distinct rect analysed at the CLI's vertex
// budgets and the profile's opaque area, then choose_for_target with
// opaque merging on. What the wasm cannot do: Clipper 6 is not in it
// (clip_hidden_parts does nothing there), so --target plans without
// clipping hidden parts, as optimize with --no-clip-hidden does.
struct SceneBuild {
    Scene scene;
    std::vector<std::vector<std::uint8_t>> pixels; // per image, RGBA8 rows packed
    // Per image, what the pipeline decodes once: the file (path) and its
    // colour key, or the fill colour. Images with equal keys share analyses.
    std::vector<std::string> decode_key;
    // The pixels' bytes so far, against limits::kMaxDecodedBytes.
    std::uint64_t decoded_bytes = 0;
};

std::string mib_text(std::uint64_t bytes) { return std::to_string((bytes + (std::uint64_t(1) << 20) - 1) >> 20) + " MiB"; }

Handles<SceneBuild> g_scenes;

SceneBuild* scene_of(double handle) {
    SceneBuild* s = g_scenes.get(handle);
    if (!s) fail("scene: handle " + number_text(handle) + " is not a live scene");
    return s;
}

void append_meshes(const SceneMeshes& m) {
    const SceneStats& s = m.stats;
    for (std::int64_t v : {s.elements, s.draw_calls, s.triangles, s.depth_levels, s.depth_bits, s.graph_edges}) g_result.push_back(double(v));
    g_result.push_back(m.depth_test ? 1 : 0);
    g_result.push_back(double(m.draws.size()));
    for (const Draw& d : m.draws) {
        g_result.push_back(d.image);
        g_result.push_back(d.pass == Pass::opaque ? 0 : 1);
        g_result.push_back(double(int(d.blend)));
        g_result.push_back(double(d.vertices.size() / kVertexFloats));
        g_result.push_back(double(d.indices.size()));
        for (float v : d.vertices) g_result.push_back(v);
        for (std::uint32_t i : d.indices) g_result.push_back(i);
    }
}

// The animated runs of `meshes` (the meshes files' "animated"): their
// count, then per run draw, first vertex, vertex count, animation.
void append_animated_runs(const Scene& scene, const SceneMeshes& meshes) {
    const std::vector<AnimatedRun> runs = animated_runs(scene, meshes);
    g_result.push_back(double(runs.size()));
    for (const AnimatedRun& r : runs)
        for (std::uint32_t v : {r.draw, r.first_vertex, r.vertex_count, r.animation}) g_result.push_back(double(v));
}

// pipeline::analyze_animation without the cache (the same two core steps).
ImageAnalysis analyze_animation_frames(const std::vector<ImageView>& images, const Animation& animation, const AnalyzeOptions& options) {
    const Image combined = animation_alpha(images, animation);
    ImageAnalysis a = analyze_image(combined.view(), {0, 0, combined.width, combined.height}, options);
    place_animation_analysis(a, images, animation);
    return a;
}

} // namespace

extern "C" {

// Linear memory for the caller's pixels (JavaScript cannot call malloc).
DCW_EXPORT(dcw_alloc) void* dcw_alloc(std::uint32_t bytes) { return std::malloc(bytes ? bytes : 1); }
DCW_EXPORT(dcw_free) void dcw_free(void* p) { std::free(p); }

DCW_EXPORT(dcw_last_error) const char* dcw_last_error() { return g_error.c_str(); }
DCW_EXPORT(dcw_result) const double* dcw_result() { return g_result.data(); }
DCW_EXPORT(dcw_result_size) std::uint32_t dcw_result_size() { return std::uint32_t(g_result.size()); }

// Per-image analysis (paper 2.1, 2.2) of `rect` in the RGBA8 image at
// `rgba` (width * height * 4 bytes, rows packed, non-premultiplied), with
// the options of `depthcull analyze`. `name` (UTF-8, may be null) starts
// each error message, as the CLI starts it with the file's path.
// `filter`: 0 nearest, 1 linear. `opaque_method`: 0 paper, 1 fast, 2 grow.
// On DCW_OK the result buffer holds, as doubles:
//   boundary polygon count, then per polygon its vertex count and x, y pairs;
//   the same for the opaque polygons;
//   the stats: nontransparent_texels, opaque_texels, boundary_area,
//   bbox_area, boundary_vertices, opaque_area, opaque_covered_texels,
//   opaque_coverage.
DCW_EXPORT(dcw_analyze)
int dcw_analyze(const std::uint8_t* rgba, double width, double height, double rx, double ry, double rw, double rh,
                double max_vertices, double split, double filter, double opaque_method, double max_opaque,
                double min_coverage, double min_opaque_area, const char* name) {
    g_result.clear();
    ImageAnalysis a;
    if (!analyze_args(rgba, width, height, rx, ry, rw, rh, max_vertices, split, filter, opaque_method, max_opaque, min_coverage,
                      min_opaque_area, name, &a))
        return DCW_ERROR_INVALID_ARGUMENT;
    append_polygons(a.boundary);
    append_polygons(a.opaque);
    const ImageStats& s = a.stats;
    for (double v : {double(s.nontransparent_texels), double(s.opaque_texels), s.boundary_area, s.bbox_area,
                     double(s.boundary_vertices), s.opaque_area, double(s.opaque_covered_texels), s.opaque_coverage})
        g_result.push_back(v);
    return DCW_OK;
}

// A new FrameAssembler: opaque_pass 0 or 1 (AssemblerOptions::opaque_pass),
// filter 0 nearest, 1 linear. The handle (>= 1) is the result's one number.
DCW_EXPORT(dcw_frame_new) int dcw_frame_new(double opaque_pass, double filter) {
    g_result.clear();
    std::string error;
    int pass = 1, filt = 0;
    if (!int_option("opaquePass", opaque_pass, 0, 1, &pass, &error) || !int_option("filter", filter, 0, 1, &filt, &error)) return fail(error);
    AssemblerOptions o;
    o.opaque_pass = pass != 0;
    o.filter = filt ? Filter::linear : Filter::nearest;
    g_result.push_back(double(g_frames.add(std::make_unique<Frames>(o))));
    return DCW_OK;
}

DCW_EXPORT(dcw_frame_free) void dcw_frame_free(double handle) { g_frames.free(handle); }

// A picture sprites show: `rect` of the RGBA8 texture at `rgba` (its whole
// width x height), analysed with dcw_analyze's options; `texture` is what
// the frame's draws name. The picture's id is the result's one number.
DCW_EXPORT(dcw_frame_add_image)
int dcw_frame_add_image(double handle, double texture, const std::uint8_t* rgba, double width, double height, double rx, double ry,
                        double rw, double rh, double max_vertices, double split, double filter, double opaque_method,
                        double max_opaque, double min_coverage, double min_opaque_area, const char* name) {
    g_result.clear();
    Frames* f = frames_of(handle);
    if (!f) return DCW_ERROR_INVALID_ARGUMENT;
    std::string error;
    int tex = 0;
    if (!int_option("texture", texture, 0, INT32_MAX, &tex, &error)) return fail(error);
    ImageAnalysis a;
    Rect rect;
    if (!analyze_args(rgba, width, height, rx, ry, rw, rh, max_vertices, split, filter, opaque_method, max_opaque, min_coverage,
                      min_opaque_area, name, &a, &rect))
        return DCW_ERROR_INVALID_ARGUMENT;
    SpriteImage image{tex, int(width), int(height), rect, &a};
    int id = 0;
    if (FrameStatus s = f->assembler.add_image(image, &id); s != FrameStatus::ok)
        return fail(std::string("addImage: ") + frame_status_text(s));
    g_result.push_back(id);
    return DCW_OK;
}

// An animation of `count` picture ids (doubles at `ids`). Its id is the
// result's one number.
DCW_EXPORT(dcw_frame_add_animation) int dcw_frame_add_animation(double handle, const double* ids, double count) {
    g_result.clear();
    Frames* f = frames_of(handle);
    if (!f) return DCW_ERROR_INVALID_ARGUMENT;
    std::string error;
    int n = 0;
    if (!int_option("frames", count, 1, 1 << 16, &n, &error)) return fail("addAnimation: " + error);
    std::vector<int> images(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k)
        if (!int_option("image", ids[k], 0, int(f->assembler.image_count()) - 1, &images[std::size_t(k)], &error))
            return fail("addAnimation: frame " + std::to_string(k) + ": " + error);
    int id = 0;
    if (FrameStatus s = f->assembler.add_animation(images, &id); s != FrameStatus::ok)
        return fail(std::string("addAnimation: ") + frame_status_text(s));
    g_result.push_back(id);
    return DCW_OK;
}

// The static meshes' insertion points, as a meshes file states them
// (web/src/meshes.js checked them as the C++ readers do): `count` points of
// 3 doubles (levels, first_level, blend_draw) at `points`, the file's
// depth_bits and depth_test. count 0: fully dynamic frames (assemble()).
DCW_EXPORT(dcw_frame_set_points)
int dcw_frame_set_points(double handle, const double* points, double count, double depth_bits, double depth_test) {
    g_result.clear();
    Frames* f = frames_of(handle);
    if (!f) return DCW_ERROR_INVALID_ARGUMENT;
    std::string error;
    int n = 0, bits = 0, test = 0;
    if (!int_option("insertionPoints.length", count, 0, 1 << 16, &n, &error) || !int_option("depthBits", depth_bits, 0, 62, &bits, &error) ||
        !int_option("depthTest", depth_test, 0, 1, &test, &error))
        return fail("setInsertionPoints: " + error);
    if (n > 0 && bits < 2) return fail("setInsertionPoints: insertion points need depth values (depthBits " + std::to_string(bits) + ")");
    // Every point checked before the assembler's are replaced: a refused
    // call leaves the points (and the frames they give) as they were.
    const std::int64_t denominator = bits >= 2 ? std::int64_t(1) << (bits - 2) : 0;
    std::vector<InsertionPoint> checked;
    checked.reserve(std::size_t(n));
    for (int k = 0; k < n; ++k) {
        InsertionPoint p;
        int levels = 0, first = 0, blend_draw = 0;
        const std::string at = "setInsertionPoints: point " + std::to_string(k) + ": ";
        if (!int_option("levels", points[3 * k], 0, int(kMaxDepthLevels), &levels, &error) ||
            !int_option("firstLevel", points[3 * k + 1], 0, int(kMaxDepthLevels), &first, &error) ||
            !int_option("blendDraw", points[3 * k + 2], 0, INT32_MAX, &blend_draw, &error))
            return fail(at + error);
        if (std::int64_t(first) + levels > denominator / 2)
            return fail(at + "levels " + std::to_string(first) + " + " + std::to_string(levels) + " are past the depth mapping");
        p.levels = levels;
        p.first_level = first;
        p.blend_draw = std::uint32_t(blend_draw);
        checked.push_back(p);
    }
    f->points.insertion_points = std::move(checked);
    f->points.depth_denominator = denominator;
    f->points.depth_test = test != 0;
    f->has_points = n > 0;
    return DCW_OK;
}

// Room for a frame's input: `lists` sprite counts (one per insertion
// point; 1 list without points), then `sprites` sprites of kSpriteDoubles.
// Returns the doubles' address (kept, with its capacity, for later frames;
// it moves only when a frame needs more room), 0 on a bad size.
DCW_EXPORT(dcw_frame_input) double* dcw_frame_input(double handle, double lists, double sprites) {
    Frames* f = frames_of(handle);
    std::string error;
    int nl = 0, ns = 0;
    if (!f || !int_option("lists", lists, 0, 1 << 16, &nl, &error) || !int_option("sprites", sprites, 0, int(kMaxDepthLevels), &ns, &error)) {
        if (!error.empty()) fail(error);
        return nullptr;
    }
    f->input.resize(std::size_t(nl) + std::size_t(ns) * kSpriteDoubles);
    return f->input.data();
}

// Assembles a frame from dcw_frame_input's doubles (`lists` counts, then
// the sprites, in painter's order per list), the overlap grid over the
// world rectangle bx, by, bw, bh (the camera's view). dcw_frame_info then
// points at the frame.
DCW_EXPORT(dcw_frame_assemble)
int dcw_frame_assemble(double handle, double lists, double bx, double by, double bw, double bh) {
    Frames* f = frames_of(handle);
    if (!f) return DCW_ERROR_INVALID_ARGUMENT;
    std::string error;
    int nl = 0;
    Viewport bounds;
    if (!int_option("lists", lists, 0, 1 << 16, &nl, &error) || !int_option("bounds.width", bw, 0, INT32_MAX, &bounds.width, &error) ||
        !int_option("bounds.height", bh, 0, INT32_MAX, &bounds.height, &error))
        return fail("assemble: " + error);
    if (!std::isfinite(bx) || !std::isfinite(by)) return fail("assemble: bounds.x and bounds.y must be finite");
    bounds.x = bx;
    bounds.y = by;
    if (std::size_t(nl) > f->input.size()) return fail("assemble: more lists than dcw_frame_input made room for");
    if (!f->has_points && nl != 1) return fail("assemble: without insertion points the sprites are one list, not " + std::to_string(nl));
    if (f->has_points && std::size_t(nl) > f->points.insertion_points.size())
        return fail("assemble: " + std::to_string(nl) + " sprite lists but the meshes have " +
                    std::to_string(f->points.insertion_points.size()) + " insertion points");
    std::size_t total = 0;
    for (int k = 0; k < nl; ++k) {
        int n = 0;
        if (!int_option("sprites.length", f->input[std::size_t(k)], 0, int(kMaxDepthLevels), &n, &error)) return fail("assemble: list " + std::to_string(k) + ": " + error);
        total += std::size_t(n);
    }
    if (std::size_t(nl) + total * kSpriteDoubles > f->input.size()) return fail("assemble: more sprites than dcw_frame_input made room for");
    f->sprites.resize(total);
    const double* in = f->input.data() + nl;
    for (std::size_t i = 0; i < total; ++i, in += kSpriteDoubles) {
        Sprite& s = f->sprites[i];
        const std::string at = "assemble: sprite " + std::to_string(i) + ": ";
        int blend = 0;
        if (!int_option("image", in[0], -1, INT32_MAX, &s.image, &error) || !int_option("animation", in[1], -1, INT32_MAX, &s.animation, &error) ||
            !int_option("frame", in[2], 0, INT32_MAX, &s.frame, &error) || !int_option("blend", in[13], 0, 3, &blend, &error))
            return fail(at + error);
        for (int k = 0; k < 6; ++k) s.transform[std::size_t(k)] = in[3 + k];
        for (int k = 0; k < 4; ++k) s.color[std::size_t(k)] = float(in[9 + k]);
        s.blend = Blend(blend);
    }
    f->lists.clear();
    std::size_t at = 0;
    for (int k = 0; k < nl; ++k) {
        const std::size_t n = std::size_t(f->input[std::size_t(k)]);
        f->lists.push_back(std::span<const Sprite>(f->sprites.data() + at, n));
        at += n;
    }
    const FrameStatus st = f->has_points ? f->assembler.assemble_at(f->points, f->lists, bounds, &f->frame)
                                         : f->assembler.assemble(f->lists.empty() ? std::span<const Sprite>() : f->lists[0], bounds, &f->frame);
    if (st != FrameStatus::ok) return fail(std::string("assemble: ") + frame_status_text(st));
    const AssembledFrame& fr = f->frame;
    f->draws.resize(fr.draws.size() * 5);
    for (std::size_t d = 0; d < fr.draws.size(); ++d) {
        const FrameDraw& x = fr.draws[d];
        std::uint32_t* w = f->draws.data() + 5 * d;
        w[0] = std::uint32_t(x.image);
        w[1] = x.pass == Pass::opaque ? 0 : 1;
        w[2] = std::uint32_t(x.blend);
        w[3] = x.first_index;
        w[4] = x.index_count;
    }
    f->frame_points.resize(fr.points.size() * 3);
    for (std::size_t p = 0; p < fr.points.size(); ++p) {
        f->frame_points[3 * p] = fr.points[p].static_draw;
        f->frame_points[3 * p + 1] = fr.points[p].first_draw;
        f->frame_points[3 * p + 2] = fr.points[p].end_draw;
    }
    auto address = [](const void* p) { return std::uint32_t(reinterpret_cast<std::uintptr_t>(p)); };
    const FrameStats& s = fr.stats;
    const std::uint32_t info[kInfoWords] = {address(fr.vertices.data()), std::uint32_t(fr.vertices.size()), address(fr.indices.data()),
                                            std::uint32_t(fr.indices.size()), address(f->draws.data()), std::uint32_t(fr.draws.size()),
                                            std::uint32_t(fr.opaque_draws), address(f->frame_points.data()), std::uint32_t(fr.points.size()),
                                            fr.depth_test ? 1u : 0u, std::uint32_t(s.sprites), std::uint32_t(s.draw_calls),
                                            std::uint32_t(s.opaque_draws), std::uint32_t(s.triangles), std::uint32_t(s.blend_batches),
                                            std::uint32_t(s.over_budget)};
    std::copy(std::begin(info), std::end(info), f->info);
    return DCW_OK;
}

DCW_EXPORT(dcw_frame_info) const std::uint32_t* dcw_frame_info(double handle) {
    Frames* f = frames_of(handle);
    return f ? f->info : nullptr;
}

DCW_EXPORT(dcw_scene_new) int dcw_scene_new() {
    g_result.clear();
    g_result.push_back(double(g_scenes.add(std::make_unique<SceneBuild>())));
    return DCW_OK;
}

DCW_EXPORT(dcw_scene_free) void dcw_scene_free(double handle) { g_scenes.free(handle); }

// An image of the scene: width x height RGBA8 texels at `rgba` (copied),
// `name` its id in messages, `path` the file it came from (UTF-8, may be
// null or empty: the id), which decides, as in the CLI, which images share
// analyses and meshes. `trans` a colour key 0xRRGGBB (texels of exactly
// that colour made transparent, as the CLI decodes a Tiled `trans` image)
// or -1; `fill` 0xRRGGBB or -1: a solid image of that colour,
// kFillImageSide square, no pixels read (rgba may be null). Its index is
// the result's one number.
DCW_EXPORT(dcw_scene_add_image)
int dcw_scene_add_image(double handle, const std::uint8_t* rgba, double width, double height, const char* name, const char* path,
                        double trans, double fill) {
    g_result.clear();
    SceneBuild* s = scene_of(handle);
    if (!s) return DCW_ERROR_INVALID_ARGUMENT;
    const std::string who = name && *name ? std::string(name) : std::string("image");
    std::string error;
    int w = 0, h = 0, key = -1, colour = -1;
    if (!int_option("trans", trans, -1, 0xffffff, &key, &error) || !int_option("fill", fill, -1, 0xffffff, &colour, &error))
        return fail(who + ": " + error);
    if (colour >= 0) width = height = kFillImageSide;
    if (!int_option("width", width, 1, kMaxImageSide, &w, &error) || !int_option("height", height, 1, kMaxImageSide, &h, &error))
        return fail(who + ": " + error);
    if (std::int64_t(w) * h > kMaxImageTexels)
        return fail(who + ": " + std::to_string(w) + "x" + std::to_string(h) + " image exceeds " + std::to_string(kMaxImageTexels) + " texels");
    if (!rgba && colour < 0) return fail(who + ": no pixels");
    if (s->scene.images.size() >= kMaxSceneImagesWasm) return fail(who + ": more than " + std::to_string(kMaxSceneImagesWasm) + " images");
    // The CLI's bound on decoded images (pipeline::prepare_scene, summed
    // from the headers before any decode), checked before the copy: each
    // image here holds its own copy, so each counts.
    const std::uint64_t bytes = std::uint64_t(w) * std::uint64_t(h) * 4;
    if (s->decoded_bytes + bytes > limits::kMaxDecodedBytes)
        return fail(who + ": " + std::to_string(w) + "x" + std::to_string(h) + " brings the decoded images to " + mib_text(s->decoded_bytes + bytes) +
                    ", over the limit of " + mib_text(limits::kMaxDecodedBytes) + " (kMaxDecodedBytes)");
    SceneImage img;
    img.id = who;
    img.path = path && *path ? std::string(path) : who;
    img.width = w;
    img.height = h;
    std::vector<std::uint8_t> pixels;
    char hex[8];
    if (colour >= 0) {
        // io::read_scene_image's fill: every texel the colour, opaque; no file.
        img.has_fill = true;
        img.fill = std::uint32_t(colour);
        img.path.clear();
        pixels.resize(std::size_t(w) * std::size_t(h) * 4);
        for (std::size_t i = 0; i < pixels.size(); i += 4) {
            pixels[i] = std::uint8_t(colour >> 16);
            pixels[i + 1] = std::uint8_t(colour >> 8);
            pixels[i + 2] = std::uint8_t(colour);
            pixels[i + 3] = 255;
        }
        std::snprintf(hex, sizeof hex, "%06x", unsigned(colour));
        s->decode_key.push_back(std::string("\nfill ") + hex);
    } else {
        pixels.assign(rgba, rgba + std::size_t(w) * std::size_t(h) * 4);
        std::string k = img.path;
        if (key >= 0) {
            // io::apply_color_key: only alpha changes.
            img.has_trans = true;
            img.trans = std::uint32_t(key);
            const std::uint8_t r = std::uint8_t(key >> 16), g = std::uint8_t(key >> 8), b = std::uint8_t(key);
            for (std::size_t i = 0; i < pixels.size(); i += 4)
                if (pixels[i] == r && pixels[i + 1] == g && pixels[i + 2] == b) pixels[i + 3] = 0;
            std::snprintf(hex, sizeof hex, "%06x", unsigned(key));
            k += std::string("\n") + hex;
        }
        s->decode_key.push_back(k);
    }
    s->scene.images.push_back(img);
    s->pixels.push_back(std::move(pixels));
    s->decoded_bytes += bytes;
    g_result.push_back(double(s->scene.images.size() - 1));
    return DCW_OK;
}

// An animation (a Tiled animated tile): `count` frames at `frames`, 6
// doubles each: image, rect x, y, w, h, duration (ms); frames of one size,
// within their images, checked as the scene JSON reader and
// pipeline::prepare_scene check them. Its index is the result's one number.
DCW_EXPORT(dcw_scene_add_animation) int dcw_scene_add_animation(double handle, const double* frames, double count) {
    g_result.clear();
    SceneBuild* s = scene_of(handle);
    if (!s) return DCW_ERROR_INVALID_ARGUMENT;
    const std::string at = "animation " + std::to_string(s->scene.animations.size()) + ": ";
    std::string error;
    int n = 0;
    if (!int_option("frames.length", count, 1, int(limits::kMaxAnimationFrames), &n, &error)) return fail(at + error);
    if (s->scene.animations.size() >= kMaxSceneElementsWasm) return fail(at + "more than " + std::to_string(kMaxSceneElementsWasm) + " animations");
    Animation animation;
    for (int k = 0; k < n; ++k) {
        const double* f = frames + 6 * k;
        const std::string where = at + "frames[" + std::to_string(k) + "].";
        AnimationFrame frame;
        if (!int_option((where + "image").c_str(), f[0], 0, int(s->scene.images.size()) - 1, &frame.image, &error) ||
            !int_option((where + "rect.x").c_str(), f[1], 0, kMaxImageSide, &frame.rect.x, &error) ||
            !int_option((where + "rect.y").c_str(), f[2], 0, kMaxImageSide, &frame.rect.y, &error) ||
            !int_option((where + "rect.width").c_str(), f[3], 1, kMaxImageSide, &frame.rect.w, &error) ||
            !int_option((where + "rect.height").c_str(), f[4], 1, kMaxImageSide, &frame.rect.h, &error) ||
            !int_option((where + "duration").c_str(), f[5], 0, INT32_MAX, &frame.duration_ms, &error))
            return fail(at + error);
        const SceneImage& img = s->scene.images[std::size_t(frame.image)];
        if (frame.rect.x + frame.rect.w > img.width || frame.rect.y + frame.rect.h > img.height)
            return fail(at + "frame " + std::to_string(k) + " rect is outside image \"" + img.id + "\"");
        if (k && (frame.rect.w != animation.frames[0].rect.w || frame.rect.h != animation.frames[0].rect.h))
            return fail(at + "frames differ in size");
        animation.frames.push_back(frame);
    }
    const Rect& r0 = animation.frames[0].rect;
    const std::uint64_t texels = std::uint64_t(n) * std::uint64_t(r0.w) * std::uint64_t(r0.h);
    if (texels > limits::kMaxAnimationTexels)
        return fail(at + std::to_string(n) + " frames of " + std::to_string(r0.w) + "x" + std::to_string(r0.h) + " are " + std::to_string(texels) +
                    " texels, more than " + std::to_string(limits::kMaxAnimationTexels) + " (kMaxAnimationTexels)");
    s->scene.animations.push_back(std::move(animation));
    g_result.push_back(double(s->scene.animations.size() - 1));
    return DCW_OK;
}

// An element, in painter's order: `rect` of image `image` drawn through
// the transform [a b c d e f], colour multiplier r g b a (0..1), blend 0
// alpha, 1 add, 2 multiply, 3 opaque; `animation` an animation's index or
// -1 (the element shows its first frame's image and rect).
DCW_EXPORT(dcw_scene_add_element)
int dcw_scene_add_element(double handle, double image, double rx, double ry, double rw, double rh, double a, double b, double c, double d,
                          double e, double f, double r, double g, double bl, double al, double blend, double animation) {
    SceneBuild* s = scene_of(handle);
    if (!s) return DCW_ERROR_INVALID_ARGUMENT;
    const std::string at = "element " + std::to_string(s->scene.elements.size()) + ": ";
    std::string error;
    Element el;
    int blend_value = 0;
    if (s->scene.elements.size() >= kMaxSceneElementsWasm) return fail(at + "more than " + std::to_string(kMaxSceneElementsWasm) + " elements");
    if (!int_option("image", image, 0, int(s->scene.images.size()) - 1, &el.image, &error) ||
        !int_option("rect.x", rx, 0, kMaxImageSide, &el.rect.x, &error) || !int_option("rect.y", ry, 0, kMaxImageSide, &el.rect.y, &error) ||
        !int_option("rect.width", rw, 1, kMaxImageSide, &el.rect.w, &error) ||
        !int_option("rect.height", rh, 1, kMaxImageSide, &el.rect.h, &error) || !int_option("blend", blend, 0, 3, &blend_value, &error))
        return fail(at + error);
    const SceneImage& img = s->scene.images[std::size_t(el.image)];
    if (el.rect.x + el.rect.w > img.width || el.rect.y + el.rect.h > img.height)
        return fail(at + "rect " + std::to_string(el.rect.x) + "," + std::to_string(el.rect.y) + "," + std::to_string(el.rect.w) + "," +
                    std::to_string(el.rect.h) + " is outside the " + std::to_string(img.width) + "x" + std::to_string(img.height) + " image");
    const double t[6] = {a, b, c, d, e, f};
    for (int k = 0; k < 6; ++k) {
        if (!std::isfinite(t[k])) return fail(at + "transform value " + std::to_string(k) + " is not a finite number");
        // The scene JSON reader's bound: products of vertices stay finite and exact enough.
        if (std::fabs(t[k]) > limits::kMaxCoordinate)
            return fail(at + "transform value " + std::to_string(k) + " is outside +-1e9 (kMaxCoordinate)");
        el.transform[std::size_t(k)] = t[k];
    }
    const double col[4] = {r, g, bl, al};
    for (int k = 0; k < 4; ++k) {
        if (!(col[k] >= 0 && col[k] <= 1)) return fail(at + "colour value " + std::to_string(k) + " is outside 0..1");
        el.color[std::size_t(k)] = float(col[k]);
    }
    el.blend = Blend(blend_value);
    if (!int_option("animation", animation, -1, int(s->scene.animations.size()) - 1, &el.animation, &error)) return fail(at + error);
    if (el.animation >= 0) {
        const AnimationFrame& first = s->scene.animations[std::size_t(el.animation)].frames.front();
        if (first.image != el.image || first.rect != el.rect) return fail(at + "an animated element shows its animation's first frame (image and rect)");
    }
    s->scene.elements.push_back(el);
    return DCW_OK;
}

// Reconstructs the scene for the viewport (x, y, width, height) and filter
// (0 nearest, 1 linear), analysing with dcw_analyze's options; opaque
// polygons 0 or 1 (optimize --no-opaque: no opaque search either);
// `points` holds point_count (element, levels) pairs
// (ReconstructOptions::insertion_points, optimize --insert-at and
// --insertion-levels). `target` (UTF-8, may be null or empty): optimize
// --target NAME, a built-in profile; or, when `profile` is not null, the
// name of a calibrated profile whose ten terms `profile` holds in
// docs/cost-model.md's order (frame_us, clear_color_ns_per_pixel,
// clear_depth_ns_per_pixel, draw_call_us, texture_switch_us, triangle_us,
// triangle_perimeter_ns_per_pixel, fragment_opaque_ns, fragment_blend_ns,
// fragment_rejected_ns; the file is read by JavaScript). The result: the
// stats (elements, draw calls, triangles, depth levels, depth bits, graph
// edges), depth test, the draw count, per draw image, pass (0 opaque, 1
// blend), blend, vertex count, index count, the vertices' floats and the
// indices; the insertion points (count, then element, levels, first level,
// blend draw each); the animated runs (count, then draw, first vertex,
// vertex count, animation each); then with a target the predicted ms
// (chosen, meshes only, overpaint) and the elements dropped, drawing opaque
// polygons, reverted.
DCW_EXPORT(dcw_scene_reconstruct)
int dcw_scene_reconstruct(double handle, double vx, double vy, double vw, double vh, double filter, double max_vertices, double split,
                          double opaque_method, double max_opaque, double min_coverage, double min_opaque_area, double opaque_polygons,
                          const double* points, double point_count, const char* target, const double* profile) {
    g_result.clear();
    SceneBuild* s = scene_of(handle);
    if (!s) return DCW_ERROR_INVALID_ARGUMENT;
    std::string error;
    Scene& scene = s->scene;
    int filt = 0, opaque_flag = 1;
    // The scene JSON reader's and --viewport's bounds (kMaxCoordinate,
    // kMaxImageSide): a target's cost model rasterizes frames of the
    // viewport's size, so a larger one would take minutes or trap.
    if (!(std::fabs(vx) <= limits::kMaxCoordinate) || !(std::fabs(vy) <= limits::kMaxCoordinate))
        return fail("viewport: x and y must be within +-1e9 (kMaxCoordinate)");
    if (!int_option("viewport.width", vw, 1, kMaxImageSide, &scene.viewport.width, &error) ||
        !int_option("viewport.height", vh, 1, kMaxImageSide, &scene.viewport.height, &error))
        return fail(error + " (kMaxImageSide)");
    if (!int_option("filter", filter, 0, 1, &filt, &error) ||
        !int_option("opaquePolygons", opaque_polygons, 0, 1, &opaque_flag, &error))
        return fail(error);
    scene.viewport.x = vx;
    scene.viewport.y = vy;
    scene.filter = filt ? Filter::linear : Filter::nearest;
    // The options checked once (dcw_analyze's words) on a 1x1 probe.
    const std::uint8_t probe[4] = {0, 0, 0, 0};
    ImageAnalysis unused;
    if (!analyze_args(probe, 1, 1, 0, 0, 1, 1, max_vertices, split, filt, opaque_method, max_opaque, min_coverage, min_opaque_area,
                      nullptr, &unused))
        return DCW_ERROR_INVALID_ARGUMENT;
    AnalyzeOptions analyze;
    analyze.boundary.max_vertices = int(max_vertices);
    analyze.boundary.split_parts = split != 0;
    analyze.filter = scene.filter;
    analyze.opaque.method = opaque_method == 0 ? OpaqueMethod::paper : opaque_method == 2 ? OpaqueMethod::grow : OpaqueMethod::fast;
    analyze.opaque.max_polygons = int(max_opaque);
    analyze.opaque.min_coverage = min_coverage;
    analyze.opaque.min_area = int(min_opaque_area);
    // optimize --no-opaque skips the opaque search rather than drop its result.
    if (!opaque_flag) analyze.opaque.max_polygons = 0;

    const bool targeted = target && *target;
    CostProfile cost;
    if (targeted && profile) {
        cost.name = target;
        double CostProfile::* const terms[] = {&CostProfile::frame_us, &CostProfile::clear_color_ns_per_pixel, &CostProfile::clear_depth_ns_per_pixel,
                                               &CostProfile::draw_call_us, &CostProfile::texture_switch_us, &CostProfile::triangle_us,
                                               &CostProfile::triangle_perimeter_ns_per_pixel, &CostProfile::fragment_opaque_ns,
                                               &CostProfile::fragment_blend_ns, &CostProfile::fragment_rejected_ns};
        for (std::size_t k = 0; k < std::size(terms); ++k) cost.*terms[k] = profile[k];
        std::string what;
        if (!profile_is_complete(cost, &what)) return fail("target: profile '" + cost.name + "': \"" + what + "\" is not a finite number >= 0");
    } else if (targeted && !builtin_profile(target, &cost)) {
        std::string names;
        for (const std::string& n : builtin_profile_names()) names += (names.empty() ? "" : ", ") + n;
        return fail("target: '" + std::string(target) + "' is not a built-in profile (" + names + "; or pass a profile from depthcull calibrate)");
    }
    // What optimize plans without its target, with a warning (limits.h);
    // here, where no warning reaches the caller, an error before the work.
    if (targeted && scene.elements.size() > limits::kMaxTargetElements)
        return fail("target: " + std::to_string(scene.elements.size()) + " elements, more than the " + std::to_string(limits::kMaxTargetElements) +
                    " a target weighs (kMaxTargetElements); reconstruct without a target, or only the elements in view");
    // Distinct analyses in first-use order, as pipeline::prepare_scene's:
    // per (decoded image, rect), and per animation for animated elements.
    std::map<std::tuple<int, std::string, int, int, int, int>, int> key_of;
    std::vector<int> element_key(scene.elements.size());
    std::vector<std::size_t> first_use;
    for (std::size_t i = 0; i < scene.elements.size(); ++i) {
        const Element& e = scene.elements[i];
        const auto key = e.animation >= 0 ? std::make_tuple(e.animation, std::string(), 0, 0, 0, 0)
                                          : std::make_tuple(-1, s->decode_key[std::size_t(e.image)], e.rect.x, e.rect.y, e.rect.w, e.rect.h);
        auto [it, fresh] = key_of.emplace(key, int(first_use.size()));
        if (fresh) first_use.push_back(i);
        element_key[i] = it->second;
    }
    std::vector<ImageView> views;
    for (std::size_t i = 0; i < scene.images.size(); ++i)
        views.push_back(ImageView{s->pixels[i].data(), scene.images[i].width, scene.images[i].height, std::ptrdiff_t(scene.images[i].width) * 4});
    auto analyze_key = [&](std::size_t k, const AnalyzeOptions& o) {
        const Element& e = scene.elements[first_use[k]];
        return e.animation >= 0 ? analyze_animation_frames(views, scene.animations[std::size_t(e.animation)], o)
                                : analyze_image(views[std::size_t(e.image)], e.rect, o);
    };
    ReconstructOptions reconstruct;
    reconstruct.opaque_polygons = opaque_flag != 0;
    std::vector<InsertionPoint> insertion_points;
    int np = 0;
    if (!int_option("insertionPoints.length", point_count, 0, 1 << 16, &np, &error)) return fail(error);
    for (int k = 0; k < np; ++k) {
        int element = 0, levels = 0;
        const std::string at = "insertionPoints[" + std::to_string(k) + "].";
        if (!int_option((at + "element").c_str(), points[2 * k], 0, int(scene.elements.size()), &element, &error) ||
            !int_option((at + "levels").c_str(), points[2 * k + 1], 0, int(kMaxDepthLevels), &levels, &error))
            return fail(error);
        if (k && std::size_t(element) < insertion_points.back().element)
            return fail(at + "element: " + std::to_string(element) + " is before the previous point's (points go in element order)");
        InsertionPoint p;
        p.element = std::size_t(element);
        p.levels = levels;
        insertion_points.push_back(p);
    }
    SceneMeshes meshes;
    ReconstructStatus st;
    TargetChoice choice;
    std::vector<ImageAnalysis> analyses;
    if (!targeted) {
        analyses.reserve(first_use.size());
        for (std::size_t k = 0; k < first_use.size(); ++k) analyses.push_back(analyze_key(k, analyze));
        std::vector<const ImageAnalysis*> per_element(scene.elements.size());
        for (std::size_t i = 0; i < per_element.size(); ++i) per_element[i] = &analyses[std::size_t(element_key[i])];
        reconstruct.insertion_points = insertion_points;
        reconstruct.element_spans = !scene.animations.empty();
        st = reconstruct_scene(scene, per_element, reconstruct, &meshes);
    } else {
        // pipeline::plan_target: opaque merging on; its budgets and opaque
        // area, for the default's opaque polygons and (issue 25) for
        // OpaqueMethod::cover's pieces, the plan predicted faster kept (the
        // fast one on ties); the choice made before optimize adds the
        // insertion points.
        reconstruct.merge_opaque = true;
        // Each plan also drawn without a depth buffer where predicted
        // faster, unless what the final reconstruction adds (sprites at
        // insertion points, animations' element spans) needs the depth test.
        {
            ReconstructOptions final_options = reconstruct;
            final_options.insertion_points = insertion_points;
            final_options.element_spans = !scene.animations.empty();
            reconstruct.depthless = depthless_possible(final_options);
        }
        const std::vector<int> budgets = target_budgets(analyze.boundary.max_vertices);
        analyze.opaque.min_area = depthcull::min_opaque_area(cost); // the function, not the parameter
        const std::size_t nb = budgets.size();
        std::vector<OpaqueMethod> methods{analyze.opaque.method};
        if (analyze.opaque.method == OpaqueMethod::fast && analyze.opaque.max_polygons > 0) methods.push_back(OpaqueMethod::cover);
        std::vector<std::vector<ImageAnalysis>> planned(methods.size());
        for (std::size_t m = 0; m < methods.size(); ++m) {
            std::vector<ImageAnalysis>& these = planned[m];
            these.reserve(first_use.size() * nb);
            for (std::size_t k = 0; k < first_use.size(); ++k)
                for (int b : budgets) {
                    AnalyzeOptions o = analyze;
                    o.boundary.max_vertices = b;
                    o.opaque.method = methods[m];
                    if (methods[m] == OpaqueMethod::cover) o.opaque.max_polygons = kCoverPlanPolygons;
                    these.push_back(analyze_key(k, o));
                }
            std::vector<TargetCandidates> candidates(first_use.size());
            for (std::size_t k = 0; k < first_use.size(); ++k)
                for (std::size_t b = 0; b < nb; ++b) {
                    candidates[k].analyses.push_back(&these[k * nb + b]);
                    candidates[k].max_vertices.push_back(budgets[b]);
                }
            TargetChoice c = choose_for_target(scene, candidates, element_key, cost, reconstruct);
            if (m == 0 || c.predicted_ms < choice.predicted_ms) choice = std::move(c);
        }
        ReconstructOptions chosen = reconstruct;
        chosen.opaque_polygons = reconstruct.opaque_polygons && choice.opaque_pass;
        chosen.depthless = choice.depthless;
        chosen.insertion_points = insertion_points;
        chosen.element_spans = !scene.animations.empty();
        st = reconstruct_scene(scene, choice.analysis, chosen, &meshes);
    }
    if (st == ReconstructStatus::too_many_depth_levels)
        return fail(std::string("reconstruct: the scene needs more depth levels than a 24-bit depth buffer resolves") +
                    (insertion_points.empty() ? "" : " (overlap chains and the insertion points' levels)"));
    if (st != ReconstructStatus::ok) return fail("reconstruct: invalid scene (an element names a missing image or analysis)");
    append_meshes(meshes);
    g_result.push_back(double(meshes.insertion_points.size()));
    for (const InsertionPoint& p : meshes.insertion_points)
        for (double v : {double(p.element), double(p.levels), double(p.first_level), double(p.blend_draw)}) g_result.push_back(v);
    append_animated_runs(scene, meshes);
    if (targeted)
        for (double v : {choice.predicted_ms, choice.meshes_only_ms, choice.overpaint_ms, double(choice.elements_dropped),
                         double(choice.elements_opaque), double(choice.elements_reverted)})
            g_result.push_back(v);
    return DCW_OK;
}

} // extern "C"
