// An engine's frame loop with depthcull::runtime, headless: read this top to
// bottom. The "engine" here is examples/headless_host.h, 60 lines of EGL (no window: Mesa's
// surfaceless platform and an offscreen framebuffer); yours has SDL, GLFW or
// a platform layer instead, and passes its own loader the same way.
//
//   runtime_frame SCENE.json [OUT.png]
//
// Draws the scene overpainted and optimized and counts the pixels that
// differ (only pixel centres exactly on a texel edge may: see
// docs/engine-integration.md, "Pixel for pixel"), then runs three frames with moving sprites (dynamic elements) on
// top of the optimized static scene. With OUT.png, writes the last frame.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "headless_host.h"
#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "depthcull/runtime.h"
#include "depthcull/scene.h"

using namespace depthcull;

namespace {

using example::Host;
using example::gl_loader;

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SCENE.json [OUT.png]\n", argv[0]);
        return 2;
    }
    try {
        // ---- Asset build side (usually `depthcull optimize` at build time):
        // the scene, its images, their analysis, the static meshes with
        // room for 64 moving sprites in front.
        pipeline::OptimizeOptions options;
        options.reconstruct.reserved_dynamic_levels = 64;
        const pipeline::OptimizeResult result = pipeline::optimize(argv[1], options);
        if (result.status != ReconstructStatus::ok) throw depthcull::Error(std::string(argv[1]) + ": reconstruction failed");
        const pipeline::PreparedScene& p = result.prepared;
        const SceneMeshes& static_meshes = result.meshes;
        const Viewport& view = p.scene.viewport;

        // ---- Engine start-up: context, then the runtime renderer.
        Host host;
        if (!host.open(view.width, view.height)) {
            std::fprintf(stderr, "runtime_frame: no headless OpenGL 3.3 context (needs Mesa's EGL), skipped\n");
            return 77;
        }
        std::string error;
        auto renderer = runtime::Renderer::create(&gl_loader, &error);
        if (!renderer) throw depthcull::Error(error);
        std::printf("runtime renderer on %s\n", renderer->gl_version().c_str());
        const std::vector<ImageView> images = p.views();
        if (renderer->upload_images(images, p.scene.filter) != runtime::Status::ok) throw depthcull::Error(renderer->error());

        // flip_y false: the framebuffer is read back top row first. A window
        // (row 0 at the bottom) keeps the default, true.
        const runtime::Camera camera = runtime::camera_of(view, false);
        runtime::FrameOptions clear;
        clear.clear_color = true;

        // ---- The same frame two ways: overpaint, then optimized.
        renderer->set_meshes(overpaint_meshes(p.scene));
        renderer->draw(camera, {}, clear);
        const Image overpainted = host.read(view.width, view.height);
        renderer->set_meshes(static_meshes);
        runtime::FrameCounts counts;
        renderer->draw(camera, {}, clear, &counts);
        const Image optimized = host.read(view.width, view.height);
        std::int64_t differ = 0;
        for (std::size_t i = 0; i < optimized.rgba.size(); i += 4)
            differ += std::memcmp(&optimized.rgba[i], &overpainted.rgba[i], 4) != 0;
        std::printf("optimized: %" PRId64 " draw calls, %" PRId64 " triangles; %" PRId64 " pixels differ from overpaint\n",
                    counts.draw_calls, counts.triangles, differ);

        // ---- The frame loop: sprites move, the static meshes stay uploaded.
        // add_dynamic_elements yields only this frame's own draws, which
        // draw() uploads into buffers reserved once.
        renderer->reserve_dynamic(4096, 8192);
        const std::size_t sprites = std::min<std::size_t>(8, p.scene.elements.size());
        SceneMeshes dynamic;
        for (int frame = 0; frame < 3; ++frame) {
            std::vector<Element> moving;
            std::vector<const ImageAnalysis*> analyses;
            for (std::size_t k = 0; k < sprites; ++k) {
                const std::size_t source = p.scene.elements.size() - 1 - k;
                Element e = p.scene.elements[source];
                const double angle = 0.4 * frame + 6.2831853 * double(k) / double(sprites);
                e.transform = {1, 0, 0, 1, view.x + view.width / 2.0 + 120 * std::cos(angle), view.y + view.height / 2.0 + 80 * std::sin(angle)};
                moving.push_back(e);
                analyses.push_back(p.analysis.of(source));
            }
            if (add_dynamic_elements(static_meshes, p.scene, moving, analyses, &dynamic) != ReconstructStatus::ok)
                throw depthcull::Error("more moving sprites than reserved depth levels");
            if (renderer->draw(camera, dynamic.draws, clear, &counts) != runtime::Status::ok) throw depthcull::Error(renderer->error());
            std::printf("frame %d: %zu moving sprites, %" PRId64 " draw calls\n", frame, moving.size(), counts.draw_calls);
        }
        if (argc > 2) io::write_png(argv[2], host.read(view.width, view.height).view());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "runtime_frame: error: %s\n", e.what());
        return 1;
    }
}
