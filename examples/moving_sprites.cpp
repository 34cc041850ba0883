// Moving characters between a map's layers, headless (issue 23; read
// docs/engine-integration.md, "Moving sprites between layers"). The
// static scene is reconstructed once with an insertion point (its first
// object layer, or the middle of its elements) and goes through the
// binary meshes file a game loads; each frame the camera scrolls, the
// characters walk, FrameAssembler gives them depths in the point's
// reserved range and depthcull::runtime draws static + moving.
//
//   moving_sprites SCENE [FRAMES] [SPRITES] [--compare]
//
// --compare: also draws each frame as plain sprite batching and as meshes
// only, and prints draws, triangles, fragments, CPU ms per mode.
//
// Prints each tenth frame's stats and, at the end, the pixels where the
// last frame differs from overpainting the same elements in layer order
// (exit 1 when any lies off a texel edge).
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>

#include "depthcull/frame.h"
#include "headless_host.h"
#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "depthcull/render.h"
#include "depthcull/runtime.h"
#include "depthcull/scene.h"

using namespace depthcull;

namespace {

using example::Host;
using example::gl_loader;

} // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SCENE [FRAMES] [SPRITES]\n", argv[0]);
        return 2;
    }
    const int frames = argc > 2 ? std::atoi(argv[2]) : 60, count = argc > 3 ? std::atoi(argv[3]) : 200;
    if (frames <= 0 || count <= 0 || count > 100000) {
        std::fprintf(stderr, "moving_sprites: FRAMES and SPRITES must be positive (SPRITES at most 100000)\n");
        return 2;
    }
    try {
        // ---- Asset build side: scene, analysis, static meshes with a depth
        // range reserved for `count` sprites at the insertion point.
        // The scene, its pixels and analysis first (no meshes yet): where
        // the sprites go depends on it.
        pipeline::OptimizeOptions options;
        options.reconstruct_meshes = false;
        const pipeline::OptimizeResult analyzed = pipeline::optimize(argv[1], options);
        const pipeline::PreparedScene& p = analyzed.prepared;
        if (p.scene.elements.empty()) throw depthcull::Error(std::string(argv[1]) + ": no elements");
        const std::size_t at = p.scene.insertion_points.empty() ? p.scene.elements.size() / 2 : p.scene.insertion_points[0];
        // Then the meshes, from the scene and analysis in memory.
        options.reconstruct_meshes = true;
        options.reconstruct.insertion_points = {{at, count}};
        const pipeline::OptimizeResult optimized = pipeline::optimize(pipeline::SceneSource{p.scene, p.analysis}, options);
        if (optimized.status != ReconstructStatus::ok) throw depthcull::Error(std::string(argv[1]) + ": reconstruction failed");
        const SceneMeshes& built = optimized.meshes;
        // What the asset build writes (`depthcull optimize --insert-at ...
        // --binary level.bin`) and the game loads (io::read_meshes): the
        // reserved range travels in the file's insertion points.
        const std::string file = io::meshes_to_binary(io::meshes_document(p.scene, std::move(built)), "");
        const io::MeshesDocument loaded = io::meshes_from_binary(file, "level.bin");
        const SceneMeshes& static_meshes = loaded.meshes;
        const InsertionPoint& point = static_meshes.insertion_points.at(0);
        std::printf("%zu static elements, %" PRId64 " static draws (%zu KB of binary meshes); %d sprites at element %zu: depth levels %" PRId64
                    "..%" PRId64 ", blend draws from %u on in front of them\n",
                    p.scene.elements.size(), static_meshes.stats.draw_calls, file.size() / 1024, count, point.element, point.first_level,
                    point.first_level + point.levels - 1, point.blend_draw);

        // ---- Load time: one picture per distinct analysis (the characters'
        // images), analysed once.
        FrameAssembler assembler;
        std::vector<int> pictures;
        std::vector<std::size_t> example_element;
        std::vector<std::uint8_t> seen(p.analysis.images.size(), 0);
        for (std::size_t e = 0; e < p.scene.elements.size(); ++e) {
            const std::uint32_t a = p.analysis.of_element[e];
            if (seen[a]) continue;
            seen[a] = 1;
            const Element& el = p.scene.elements[e];
            const SceneImage& img = p.scene.images[std::size_t(el.image)];
            int id = -1;
            if (assembler.add_image({el.image, img.width, img.height, el.rect, &p.analysis.images[a]}, &id) != FrameStatus::ok)
                continue;
            pictures.push_back(id);
            example_element.push_back(e);
        }

        // ---- Engine start-up.
        const Viewport world = p.scene.viewport;
        const int width = std::min(world.width, 640), height = std::min(world.height, 480);
        Host host;
        if (!host.open(width, height)) {
            std::fprintf(stderr, "moving_sprites: no headless OpenGL 3.3 context (needs Mesa's EGL), skipped\n");
            return 77;
        }
        std::string error;
        auto renderer = runtime::Renderer::create(&gl_loader, &error);
        if (!renderer) throw depthcull::Error(error);
        const std::vector<ImageView> images = p.views();
        if (renderer->upload_images(images, p.scene.filter) != runtime::Status::ok) throw depthcull::Error(renderer->error());
        if (renderer->set_meshes(static_meshes) != runtime::Status::ok) throw depthcull::Error(renderer->error());

        // Characters: walking left or right, facing their way (a flip),
        // bobbing; positions from a fixed seed.
        std::vector<Sprite> sprites(static_cast<std::size_t>(count));
        std::vector<double> x0(sprites.size()), y0(sprites.size()), speed(sprites.size());
        std::uint32_t seed = 23;
        auto next = [&] { return double((seed = seed * 1664525u + 1013904223u) >> 8) / double(1 << 24); };
        for (std::size_t i = 0; i < sprites.size(); ++i) {
            const std::size_t k = std::size_t(next() * double(pictures.size())) % pictures.size();
            sprites[i].image = pictures[k];
            sprites[i].color = p.scene.elements[example_element[k]].color;
            sprites[i].blend = p.scene.elements[example_element[k]].blend;
            x0[i] = world.x + next() * world.width, y0[i] = world.y + next() * world.height, speed[i] = next() * 4 - 2;
        }
        auto move = [&](int f) {
            for (std::size_t i = 0; i < sprites.size(); ++i) {
                const double facing = speed[i] < 0 ? -1 : 1;
                const double x = std::fmod(x0[i] + speed[i] * f - world.x + 10 * world.width, double(world.width)) + world.x;
                sprites[i].transform = {facing, 0, 0, 1, x, y0[i] + 2 * std::sin(0.3 * f + double(i))};
            }
        };
        // The same frame as one scene: static and moving elements in layer order.
        auto both_of = [&](const Viewport& v) {
            Scene both = p.scene;
            both.viewport = v;
            both.elements.assign(p.scene.elements.begin(), p.scene.elements.begin() + std::ptrdiff_t(at));
            for (const Sprite& s : sprites) {
                std::size_t k = 0;
                while (pictures[k] != s.image) ++k;
                Element e = p.scene.elements[example_element[k]];
                e.transform = s.transform;
                e.animation = -1;
                both.elements.push_back(e);
            }
            both.elements.insert(both.elements.end(), p.scene.elements.begin() + std::ptrdiff_t(at), p.scene.elements.end());
            return both;
        };
        AssembledFrame frame;
        assembler.reserve(sprites.size(), &frame);
        runtime::FrameOptions frame_options;
        frame_options.clear_color = true;
        frame_options.count_samples = true;
        Viewport view{world.x, world.y, width, height};
        for (int f = 0; f < frames; ++f) {
            // The camera scrolls across the map and back.
            const double t = frames > 1 ? double(f) / (frames - 1) : 0;
            view.x = world.x + std::round((world.width - width) * (0.5 - 0.5 * std::cos(t * 6.283185307179586)));
            move(f);
            const auto start = std::chrono::steady_clock::now();
            const std::span<const Sprite> lists[1] = {sprites};
            if (assembler.assemble_at(static_meshes, lists, view, &frame) != FrameStatus::ok) throw depthcull::Error("assembly failed");
            const double assemble_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
            runtime::FrameCounts counts;
            if (renderer->draw_frame({view.x, view.y, width, height, false}, frame, frame_options, &counts) != runtime::Status::ok)
                throw depthcull::Error(renderer->error());
            if (f % 10 == 0 || f == frames - 1)
                std::printf("frame %3d camera x %6.0f: %" PRId64 " draws (%" PRId64 " moving), %" PRId64 " triangles, %" PRId64
                            " fragments, assembly %.3f ms\n",
                            f, view.x, counts.draw_calls, frame.stats.draw_calls, counts.triangles, counts.samples_passed, assemble_ms);
        }
        const Image drawn = host.read(width, height);
        // The same last frame overpainted: static and moving elements in layer order.
        const Scene both = both_of(view);
        renderer->set_meshes(overpaint_meshes(both));
        renderer->draw({view.x, view.y, width, height, false}, {}, frame_options);
        const Image overpainted = host.read(width, height);
        std::int64_t differ = 0;
        for (std::size_t i = 0; i < drawn.rgba.size(); i += 4) differ += std::memcmp(&drawn.rgba[i], &overpainted.rgba[i], 4) != 0;
        // Only pixel centres exactly on a texel edge may differ (docs/
        // engine-integration.md, "Pixel for pixel").
        const std::int64_t off = differ ? render::count_off_texel_edges(drawn.view(), overpainted.view(), both) : 0;
        std::printf("last frame vs overpaint of the same layers: %" PRId64 " pixels differ, %" PRId64 " off texel edges\n", differ, off);
        if (off != 0) return 1;
        if (argc > 4 && std::strcmp(argv[4], "--compare") == 0) {
            // What engines do today against depth culling, frame by frame,
            // modes in turn (each frame starts with a different one), CPU
            // time of building and drawing the frame to glFinish (run with
            // LP_NUM_THREADS=1 so llvmpipe's rendering counts on one core):
            // plain batching: painter's order, runs of one texture merged,
            //   whole rects, no depth (rectangle_meshes, SortMethod::none);
            // meshes only: the same reordered by the element graph (paper's
            //   Table 2 "Meshes only", graph built every frame);
            // depth-culled: static meshes + FrameAssembler.
            auto Finish = reinterpret_cast<PFNGLFINISHPROC>(eglGetProcAddress("glFinish"));
            struct Sum {
                double cpu_ms = 0;
                std::int64_t draws = 0, triangles = 0, fragments = 0, differ = 0, off_edges = 0;
            } sums[3];
            const char* names[3] = {"plain batching", "meshes only", "depth-culled"};
            auto cpu_ms = [] {
                timespec t{};
                clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
                return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
            };
            runtime::FrameOptions o;
            o.clear_color = true;
            for (int f = 0; f < frames; ++f) {
                move(f);
                // The reference: overpaint of the same layers (untimed).
                const Scene both_now = both_of(view);
                renderer->set_meshes(overpaint_meshes(both_now));
                renderer->draw({view.x, view.y, width, height, false}, {}, o);
                const Image reference = host.read(width, height);
                for (int k = 0; k < 3; ++k) {
                    const int mode = (f + k) % 3;
                    const double start = cpu_ms();
                    runtime::FrameCounts counts;
                    if (mode < 2) {
                        ReconstructOptions ro;
                        ro.sort = mode == 0 ? SortMethod::none : SortMethod::batch;
                        SceneMeshes m;
                        rectangle_meshes(both_of(view), ro, &m);
                        renderer->set_meshes(m);
                        renderer->draw({view.x, view.y, width, height, false}, {}, o, &counts);
                    } else {
                        const std::span<const Sprite> lists[1] = {sprites};
                        assembler.assemble_at(static_meshes, lists, view, &frame);
                        renderer->set_meshes(static_meshes); // already there in a game; the others replaced it
                        renderer->draw_frame({view.x, view.y, width, height, false}, frame, o, &counts);
                    }
                    Finish();
                    Sum& sum = sums[mode];
                    sum.cpu_ms += cpu_ms() - start;
                    sum.draws += counts.draw_calls, sum.triangles += counts.triangles;
                    // Fragments shaded: counted in a second, untimed draw.
                    runtime::FrameOptions counting = o;
                    counting.count_samples = true;
                    if (mode < 2) renderer->draw({view.x, view.y, width, height, false}, {}, counting, &counts);
                    else renderer->draw_frame({view.x, view.y, width, height, false}, frame, counting, &counts);
                    sum.fragments += counts.samples_passed;
                    const Image image = host.read(width, height);
                    std::int64_t d = 0;
                    for (std::size_t i = 0; i < image.rgba.size(); i += 4) d += std::memcmp(&image.rgba[i], &reference.rgba[i], 4) != 0;
                    sum.differ += d;
                    if (d) sum.off_edges += render::count_off_texel_edges(image.view(), reference.view(), both_now);
                }
            }
            std::printf("\n%d frames, %d moving sprites, %dx%d, per frame (mean):\n", frames, count, width, height);
            std::printf("%-15s %8s %10s %12s %10s %16s %14s\n", "mode", "draws", "triangles", "fragments", "CPU ms", "pixels differing",
                        "off texel edge");
            for (int m = 0; m < 3; ++m)
                std::printf("%-15s %8.1f %10.0f %12.0f %10.2f %16.1f %14.1f\n", names[m], double(sums[m].draws) / frames,
                            double(sums[m].triangles) / frames, double(sums[m].fragments) / frames, sums[m].cpu_ms / frames,
                            double(sums[m].differ) / frames, double(sums[m].off_edges) / frames);
            std::printf("(pixels differing: from the overpaint of the same layers, every frame; off texel edge: of those, not a\n"
                        " pixel centre exactly on a texel edge)\n");
        }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "moving_sprites: %s\n", e.what());
        return 1;
    }
}
