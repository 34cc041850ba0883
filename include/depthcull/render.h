// depthcull: drawing scenes and measuring them (paper 3, Table 2).
//
// The analyzers that count what a renderer must shade (analyze_overdraw,
// ideal_overdraw) need no GL and live in the core (depthcull/overdraw.h).
// The GL renderer draws a SceneMeshes headlessly (EGL, no window) and measures
// draw calls, triangles, fragments passing the depth test (GL_SAMPLES_PASSED)
// and time per frame. Pictures of overdraw counts (heatmaps) are drawn by
// depthcull::report (report::overdraw_heatmap).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "depthcull/cost.h"
#include "depthcull/error.h"
#include "depthcull/image.h"
#include "depthcull/overdraw.h"
#include "depthcull/scene.h"

namespace depthcull::render {

// GL failures after a context exists (shader compile, framebuffer
// incomplete, texture too large): one-line messages. A depthcull::Error,
// so a caller that stops on any error catches the one type; callers that
// add the scene's name catch this one.
struct Error : depthcull::Error {
    using depthcull::Error::Error;
};

// No OpenGL context can be made ("no OpenGL context: ...": no Mesa/EGL
// driver installed, none on the platform asked for, or a GL without the
// functions we need). Callers skip (tests) or exit (the CLI, with a hint
// to install Mesa) on this one; any other render::Error is a bug to report.
struct NoContext : Error {
    using Error::Error;
};

// ---- Comparing frames

struct ImageDiff {
    int max_channel_diff = 0;      // largest |a - b| over R, G, B, A
    std::int64_t pixels_differ = 0; // pixels where any channel differs
    bool same_size = true;
};
ImageDiff compare_images(ImageView a, ImageView b);

// Where frames of the same scene drawn from different meshes differ, as a
// diagnostic. With nearest filtering and element maps (element spans and
// element_maps) reconstruction's output must not differ at all; without
// them, or with bilinear filtering, rounding explains differences here.
// Coverage: GL snaps vertices to 1/256 pixel, so two
// triangulations whose edges lie on the same line (an element's rect edge
// in overpaint, a boundary polygon edge along it when optimized) can
// disagree about a pixel centre within about 1/512 pixel of that line.
// Sampling: vertices are floats (at x = 600 a float is good to 1/16000
// pixel), so the texel position two triangulations compute for one pixel
// differs in the last bits, and a centre that close to a texel edge may
// show either texel. Pixels within `tolerance` of a triangle edge of
// either meshes, or (when `scene` is given) of a texel edge of an element
// whose rect holds the centre, count as near_edges; any other difference
// is a real one.
struct DiffCauses {
    std::int64_t near_edges = 0; // explained by rounding, as above
    std::int64_t elsewhere = 0;  // real differences
};
inline constexpr double kEdgeTolerance = 1.0 / 64;
DiffCauses classify_differences(ImageView a, const SceneMeshes& meshes_a, ImageView b, const SceneMeshes& meshes_b,
                                const Scene* scene = nullptr, double tolerance = kEdgeTolerance);

// ---- The GL renderer

enum class GlPlatform {
    automatic,   // a hardware EGL device if there is one, else Mesa surfaceless, else any EGL device
    surfaceless, // EGL_PLATFORM_SURFACELESS_MESA only
    device,      // EGL_PLATFORM_DEVICE_EXT only (eglQueryDevicesEXT)
};

struct GlOptions {
    GlPlatform platform = GlPlatform::automatic;
};

struct FrameCounts {
    std::int64_t draw_calls = 0;      // draws with at least one triangle
    std::int64_t triangles = 0;
    std::int64_t samples_passed = 0;  // GL_SAMPLES_PASSED over the frame
};

// One EGL context with an offscreen framebuffer (RGBA8 + DEPTH_COMPONENT24)
// the size of the meshes' viewport. Use each from one thread; several on
// one thread are fine (each makes its context current before GL calls).
class GlRenderer {
public:
    // Never null. Throws NoContext when no context can be made, Error when
    // the shaders do not build ("no usable OpenGL: ...", a bug to report,
    // not to skip).
    static std::unique_ptr<GlRenderer> create(const GlOptions& options);
    ~GlRenderer();
    GlRenderer(const GlRenderer&) = delete;
    GlRenderer& operator=(const GlRenderer&) = delete;

    // "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6, EGL surfaceless"
    const std::string& description() const;
    // True when the GL renderer is a software rasterizer (llvmpipe, softpipe).
    bool is_software() const;

    // One texture per scene image, sampled with `filter`, clamped to edge.
    // Texel positions come from each element's window-to-texel map
    // (element_maps and Draw::element_spans given to set_meshes; per
    // triangle, from its vertices, for meshes without them), not from float-interpolated u, v, so the texel
    // a pixel shows does not depend on how its element was triangulated;
    // with nearest filtering a
    // pixel centre exactly on a texel edge takes the texel on the side the
    // fill rule gives the pixel to (see gl_renderer.cpp).
    void set_images(const std::vector<ImageView>& images, Filter filter);
    // Uploads the meshes once (one vertex buffer, triangles unindexed since
    // each carries its texel map) and sizes the framebuffer to
    // meshes.viewport. Draws name images by index. element_maps: the
    // texel_map of each element Draw::element_spans names (element_maps(
    // scene), dynamic elements' appended); triangles of no span or an
    // element past them take their map from their vertices' u, v.
    void set_meshes(const SceneMeshes& meshes, const std::vector<TexelMap>& element_maps = {});
    // Several meshes at once (all with the same viewport size), so a
    // benchmark can alternate between them frame by frame: add_meshes
    // uploads and returns a slot, select_meshes makes it the one drawn.
    // set_meshes = forget all, add, select.
    int add_meshes(const SceneMeshes& meshes, const std::vector<TexelMap>& element_maps = {});
    void select_meshes(int slot);

    // Clears and draws one frame; does not wait for the GPU.
    void draw();
    // draw() inside a GL_SAMPLES_PASSED query.
    FrameCounts draw_counted();
    // The last frame, RGBA8, row 0 at the top of the viewport.
    Image read_pixels();
    // One frame drawn and waited for (glFinish), in ms.
    double time_frame();
    // Each of `frames` frames drawn and waited for (glFinish), in ms, after
    // `warmup` untimed frames.
    std::vector<double> time_frames(int frames, int warmup);

private:
    struct Impl;
    explicit GlRenderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// ---- Hosting a renderer the caller brings (depthcull::runtime)

enum class GlApi {
    desktop, // OpenGL core, 4.5 or 3.3
    gles,    // OpenGL ES 3.0
};

// What an engine provides around depthcull::runtime, headless: an EGL
// context (no surface) current on this thread and an offscreen framebuffer
// (RGBA8 + DEPTH_COMPONENT24). For tests, `depthcull bench` and
// calibration; examples/runtime_frame.cpp shows the same in plain EGL.
class GlHost {
public:
    // Never null. Throws NoContext ("no OpenGL context: ...") when none can
    // be made.
    static std::unique_ptr<GlHost> create(const GlOptions& options, GlApi api);
    ~GlHost();
    GlHost(const GlHost&) = delete;
    GlHost& operator=(const GlHost&) = delete;

    // The loader to hand depthcull::runtime::Renderer::create (eglGetProcAddress).
    static void* get_proc_address(const char* name);
    // "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL ES 3.2 Mesa 22.3.6, EGL surfaceless"
    const std::string& description() const;
    bool is_software() const;
    // Makes the context current on this thread (create does it too).
    void make_current();
    // Binds a framebuffer of width x height, made or resized when needed.
    // Throws Error past the GL's limits.
    void bind_framebuffer(int width, int height);
    // The bound framebuffer, RGBA8, row 0 first as glReadPixels gives it
    // (the top of a view drawn with runtime::Camera::flip_y false).
    Image read_pixels();
    void finish(); // glFinish

private:
    struct Impl;
    explicit GlHost(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

// ---- Table 2: one scene drawn the three ways

enum class Mode {
    overpaint, // Table 2 "Unoptimized": overpaint_meshes
    meshes,    // Table 2 "Meshes only": rectangle_meshes
    optimized, // Table 2 "Fully optimized": reconstruct_scene
};
const char* mode_name(Mode mode); // "overpaint", "meshes", "optimized"

// The meshes a mode draws. analysis: the scene's, as reconstruct_scene
// takes them (only `optimized` reads them). options.coverage_margin
// applies to every mode (overpaint too). for_runtime: meshes for
// depthcull::runtime, which needs element spans only to animate (the
// GlRenderer samples through them): without them the optimized meshes may
// merge opaque tiles (ReconstructOptions::merge_opaque).
ReconstructStatus build_meshes(Mode mode, const Scene& scene, const SceneAnalysis& analysis, const ReconstructOptions& options,
                               SceneMeshes* out, bool for_runtime = false);

// The margin frames are compared with (ReconstructOptions::
// coverage_margin): 8x llvmpipe's 1/512 pixel snapping error and far above
// the float error of an element map (about 1e-4 texel in a frame a few
// thousand pixels wide). GlRenderer samples through element maps with a
// rect test, so with this margin in every mode nearest filtering gives the
// same frame exactly. exact_coverage: options with this margin unless one
// is set.
inline constexpr double kCoverageMargin = 1.0 / 64;
ReconstructOptions exact_coverage(ReconstructOptions options);

struct ModeMeasurement {
    Mode mode = Mode::overpaint;
    FrameCounts counts;          // draw calls, triangles, GL_SAMPLES_PASSED
    double overdraw = 0;         // samples passed / viewport pixels (Table 2 "OD")
    double cpu_overdraw = 0;     // analyze_overdraw's figure, for comparison
    double ms_median = 0;        // per frame, glFinish-synchronized
    double ms_min = 0;
    ImageDiff diff;              // this frame against overpaint's, both with exact_coverage
    DiffCauses causes;           // diff.pixels_differ split by cause
    Image frame;                 // kept when asked (MeasureOptions::keep_frames)
    OverdrawMap map;             // CPU per-pixel counts when asked
};

struct SceneMeasurement {
    int width = 0, height = 0;
    double ideal_overdraw = 0;   // ideal_overdraw(...).overdraw()
    OverdrawMap ideal_map;       // when asked
    std::vector<ModeMeasurement> modes;
};

struct MeasureOptions {
    std::vector<Mode> modes{Mode::overpaint, Mode::meshes, Mode::optimized};
    int frames = 20;             // timed frames per mode; 0: no timing
    int warmup = 3;
    bool keep_frames = false;
    bool keep_maps = false;      // per-pixel counts for heatmaps
    ReconstructOptions reconstruct;
};

// Draws `scene` in every mode of options.modes (overpaint is always drawn
// first, as the reference the others are compared to; it is reported
// only when asked for). images[i] holds Scene::images[i]. Throws Error
// when a mode's meshes cannot be built.
SceneMeasurement measure_scene(GlRenderer& renderer, const Scene& scene, const std::vector<ImageView>& images,
                               const SceneAnalysis& analysis, const MeasureOptions& options);

// ---- Frames as an engine draws them: depthcull::runtime (the plain sprite
// shader, no per-element maps or rect tests), hosted in a GlHost. What
// `depthcull bench` reports; GlRenderer stays for `render --compare`.

// Differing pixels whose centre lies on no texel edge of an element whose
// rect holds it: differences rounding cannot explain. A pixel centre
// exactly on a texel edge (within kTexelEdgeTolerance, the float rounding
// of the element's map, or a few ulps of GL's float interpolation of u, v
// where that is more: it grows with the texel gradient times the pixel's
// coordinates, and with the texture size) may show the texel on either
// side, depending on the last bits of the interpolated u, v of the
// triangle that covers it;
// anywhere else a plain renderer must draw the optimized meshes exactly
// like overpaint (ReconstructOptions::texel_margin).
inline constexpr double kTexelEdgeTolerance = 1.0 / 65536;
std::int64_t count_off_texel_edges(ImageView a, ImageView b, const Scene& scene);

struct RuntimeModeMeasurement {
    Mode mode = Mode::overpaint;
    std::int64_t draw_calls = 0;
    std::int64_t triangles = 0;
    std::int64_t fragments_rasterized = 0; // GL_SAMPLES_PASSED with the depth test off
    std::int64_t fragments_shaded = 0;     // GL_SAMPLES_PASSED as drawn
    double wall_ms = 0;                    // median per frame, glFinish each
    double cpu_ms = 0;                     // median process CPU time per frame
    ImageDiff diff;                        // against the runtime's overpaint frame
    std::int64_t off_texel_edges = 0;      // of diff.pixels_differ: count_off_texel_edges
    ExcessStats excess;                    // the shaded fragments by texel (excess_overdraw of the meshes drawn)
    Image frame;                           // when MeasureOptions::keep_frames
};

struct RuntimeMeasurement {
    int width = 0, height = 0;
    double ideal_overdraw = 0;
    std::vector<RuntimeModeMeasurement> modes;
};

// Draws `scene` in every mode of options.modes with depthcull::runtime
// (nearest or linear as scene.filter says), overpaint first as the
// reference; modes take turns frame by frame when timing. Throws Error.
RuntimeMeasurement measure_runtime(GlHost& host, const Scene& scene, const std::vector<ImageView>& images,
                                   const SceneAnalysis& analysis, const MeasureOptions& options);

// ---- Moving sprites (issue 23): what engines do today against depth
// culling, frame by frame, drawn by depthcull::runtime

enum class SpriteMode {
    batching, // plain sprite batching as engines do it: every element's rect in painter's order, runs of one texture and blend merged, no depth
    meshes,   // meshes only: static meshes and moving sprites as reordered, batched boundary polygons, no opaque pass, no depth
    culled,   // depth-culled: static meshes with an insertion point + FrameAssembler (opaque pass front to back, then blend)
};
const char* sprite_mode_name(SpriteMode mode); // "plain batching", "meshes only", "depth-culled"

struct SpriteBenchOptions {
    int sprites = 1000;
    // Fully dynamic: no static scene, only the sprites (a bunnymark: they
    // fall, bounce and overlap). Otherwise they move in the game layer.
    bool bunnymark = false;
    int frames = 60;
    std::uint32_t seed = 23;
    // The camera: the scene's viewport, cut to at most this size around its centre.
    int max_width = 1024, max_height = 768;
    // --target: the moving sprites draw a picture's opaque polygon only
    // where it pays on this profile in these frames (measure_sprites.cpp:
    // its fragments over the layers expected behind a sprite against its
    // triangles and edges); null keeps them all.
    const CostProfile* target = nullptr;
    // Checks only (tests): the modes drawn (the others' rows stay 0) and
    // whether fragments are counted (a second draw of each frame).
    std::array<bool, 3> modes{true, true, true};
    bool count_fragments = true;
};

struct SpriteFrameMeasurement {
    std::int64_t draw_calls = 0;
    std::int64_t triangles = 0;
    std::int64_t fragments_shaded = 0; // GL_SAMPLES_PASSED
    double cpu_ms = 0;                 // process CPU time: building the frame's geometry, drawing it, glFinish
    std::int64_t pixels_differ = 0;    // against the overpaint of the same layers
    std::int64_t off_texel_edges = 0;  // of those, count_off_texel_edges
};

struct SpriteMeasurement {
    Viewport camera;
    std::size_t static_elements = 0;   // in the camera (0: bunnymark)
    std::size_t insertion_element = 0; // the sprites go before this static element
    bool scene_point = false;          // it is the scene's first insertion point (else: on top)
    std::size_t pictures = 0, pictures_with_opaque = 0; // distinct pictures the sprites show; those drawing opaque polygons
    double layers_behind = 0;          // --target: layers expected behind a sprite
    std::int64_t static_draws[3] = {0, 0, 0}; // per mode, the static meshes' draws (batching: 0, built per frame)
    // frames[f][mode]: every frame, every mode (SpriteMode order).
    std::vector<std::array<SpriteFrameMeasurement, 3>> frames;
};

// N sprites taken from `scene`'s own pictures (each distinct analysed
// rect; animated elements with their frames), deterministic from
// options.seed: positions, rotations, scales 0.25-2, animation frames;
// moving in the game layer (the scene's first insertion point: a Tiled
// map's first object layer) or, with bunnymark, alone. Every frame draws
// the three modes in turns (each frame starts with another) and the
// overpaint of the same layers, untimed, as the reference. Throws Error.
SpriteMeasurement measure_sprites(GlHost& host, const Scene& scene, const std::vector<ImageView>& images, const SceneAnalysis& analysis,
                                  const SpriteBenchOptions& options);
// The table `depthcull bench --sprites / --bunnymark` prints: a row per
// frame, the three modes side by side, then their means.
std::string sprite_table(const SpriteMeasurement& m);

} // namespace depthcull::render
