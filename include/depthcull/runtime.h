// depthcull::runtime: draws SceneMeshes in the host's own OpenGL context,
// the way an engine would: a plain sprite shader (texture x vertex colour),
// the opaque pass front to back with depth writes, then the blend pass back
// to front, then the frame's dynamic elements. No EGL, no window, no GL
// loader library: the host owns the context and hands us a function that
// finds GL entry points (eglGetProcAddress, SDL_GL_GetProcAddress,
// glfwGetProcAddress). Works on OpenGL 3.3 core and OpenGL ES 3.0 (so
// WebGL 2 can follow); docs/engine-integration.md has the states, the shader
// and the blend factors, for engines that draw our meshes themselves.
//
// Errors are Status values plus a one-line message (error()); nothing here
// throws, so the C API wraps it as it is.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "depthcull/frame.h"
#include "depthcull/image.h"
#include "depthcull/scene.h"

namespace depthcull::runtime {

// Finds a GL entry point by name ("glDrawElements"); nullptr when absent.
using GlLoader = void* (*)(const char* name);

enum class Status {
    ok,
    no_gl,          // a GL function we need is missing, or the context is older than GL 3.3 / ES 3.0
    shader_failed,  // a shader does not compile or link (a driver bug or a broken context)
    bad_image,      // an image is empty or larger than GL_MAX_TEXTURE_SIZE
    bad_meshes,     // a draw names a missing image, an index past its vertices, too many vertices
    gl_error,       // glGetError reported something after our calls
};

// The part of the world a frame shows: world [x, x+width) x [y, y+height)
// (the coordinates of SceneMeshes' vertices) fills the framebuffer's
// [0, width) x [0, height). `flip_y`: true for a window's default
// framebuffer, whose row 0 is at the bottom (world y grows downwards, so the
// world's top row is drawn at the window's top); false for an offscreen
// framebuffer read back with glReadPixels, whose first row is then the
// world's top row.
struct Camera {
    double x = 0, y = 0;
    int width = 0, height = 0;
    bool flip_y = true;
};
inline Camera camera_of(const Viewport& v, bool flip_y = true) { return {v.x, v.y, v.width, v.height, flip_y}; }

// What one frame drew. Best case: as the meshes' SceneStats say.
struct FrameCounts {
    std::int64_t draw_calls = 0;
    std::int64_t triangles = 0;
    // Fragments that passed the depth test (GL_SAMPLES_PASSED), when asked
    // for with FrameOptions::count_samples on desktop GL; -1 otherwise
    // (OpenGL ES has no such query).
    std::int64_t samples_passed = -1;
};

struct FrameOptions {
    // Clears the colour buffer to transparent black first (the depth buffer
    // is always cleared, to 0, when the meshes use it).
    bool clear_color = false;
    // Wraps the frame in a GL_SAMPLES_PASSED query and waits for it.
    bool count_samples = false;
    // Measurement only: draws with the depth test off, so count_samples
    // counts every fragment rasterized (what a frame would shade without
    // depth culling). Changes the picture.
    bool no_depth_test = false;
};

// CPU and wall time of `frames` frames, each finished with glFinish
// (time_frames). Process CPU time includes the driver's rendering threads
// (llvmpipe renders on the CPU).
struct FrameTimes {
    int frames = 0;
    double wall_ms = 0;   // summed over the frames
    double cpu_ms = 0;    // process CPU time, summed
    FrameCounts counts;   // of one frame (with count_samples)
};

class Renderer {
public:
    // Loads the GL entry points through `loader` (the context must be
    // current) and builds the shaders for the context's GL or GL ES
    // version. nullptr with *error set ("no OpenGL: ...") when it cannot.
    static std::unique_ptr<Renderer> create(GlLoader loader, std::string* error);
    ~Renderer(); // deletes what it created; the context must be current
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // "OpenGL ES 3.2 Mesa 22.3.6" / "4.5 (Core Profile) Mesa 22.3.6"
    const std::string& gl_version() const;
    bool is_gles() const;
    // The message of the last call that did not return Status::ok.
    const std::string& error() const;

    // ---- Textures, one per Scene image (a Draw's `image` indexes them).
    // Either the runtime uploads RGBA8 images (non-premultiplied, as PNG
    // stores them; sampled with `filter`, clamped to edge)...
    Status upload_images(std::span<const ImageView> images, Filter filter);
    // ...or the host gives its own GL texture names (an engine that has
    // its texture cache already): RGBA, non-premultiplied, with the
    // filter the analysis assumed. The runtime neither changes nor deletes
    // them. Images that share a file may share a name.
    Status set_textures(std::span<const unsigned> gl_texture_names);
    // The names in use (the runtime's own or the host's), so a second
    // Renderer on the same context can share them.
    const std::vector<unsigned>& texture_names() const;

    // ---- Meshes
    // Uploads the static meshes once (one vertex and one index buffer,
    // GL_STATIC_DRAW), replacing any before. Draws name textures by index,
    // so call after the textures.
    Status set_meshes(const SceneMeshes& meshes);
    // Room for the dynamic draws of a frame (vertices, indices), so that a
    // frame within it allocates nothing, on the CPU or in GL. A frame with
    // more grows the buffers (once; later frames reuse them).
    Status reserve_dynamic(std::size_t vertices, std::size_t indices);

    // ---- Frames
    // Draws one frame into the bound framebuffer (which needs a depth
    // buffer, 24 bits for most scenes: SceneStats::depth_bits says):
    // glViewport(0, 0, width, height); depth cleared to 0; the opaque pass
    // (dynamic opaque draws, then static), depth test GL_GREATER with writes,
    // blending off; the blend pass (static, then dynamic) with depth writes
    // off and the blend factors of each draw's Blend. `dynamic`: the draws
    // add_dynamic_elements made for this frame (only its own, not the static
    // ones), uploaded into the reserved buffers. Allocates nothing once the
    // dynamic buffers are large enough. Leaves blending, depth test, depth
    // mask, program, vertex array and textures as it set them.
    Status draw(const Camera& camera, std::span<const Draw> dynamic = {}, const FrameOptions& options = {},
                FrameCounts* counts = nullptr);

    // Draws the static meshes (set_meshes; none for a fully dynamic frame)
    // and an assembled frame of moving sprites (FrameAssembler): the frame's
    // opaque draws, the static opaque draws, then the static blend draws
    // with each insertion point's blend draws where FramePoint puts them.
    // The depth buffer is used when the static meshes or the frame use it.
    // Uploads the frame's vertices and indices as they are; allocates
    // nothing once the frame's draw list has fit (reserve_dynamic).
    Status draw_frame(const Camera& camera, const AssembledFrame& frame, const FrameOptions& options = {},
                      FrameCounts* counts = nullptr);

    // Calibration and benchmarks: draws the static meshes `frames` times
    // (each a whole frame, glFinish after each) and returns the summed wall
    // and process CPU times, and one frame's counts.
    Status time_frames(const Camera& camera, int frames, const FrameOptions& options, FrameTimes* out);

private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

} // namespace depthcull::runtime
