// Table 2 as an engine sees it: the three modes drawn by depthcull::runtime
// (plain sprite shader) in a headless host, timed frame by frame in turns,
// with fragments counted with and without the depth test, and each frame
// compared with the runtime's own overpaint frame.
#include <algorithm>
#include <cmath>

#include "depthcull/render.h"
#include "depthcull/runtime.h"

namespace depthcull::render {

namespace {

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

bool on_texel_edge(double t, double tolerance) { return std::abs(t - std::round(t)) <= tolerance; }

// How far (texels) GL's float interpolation of a plain renderer's u or v
// may put a pixel centre from its exact texel position: a few ulps of the
// terms it sums, which grow with the texel gradient (ux, uy per pixel)
// times the coordinates (world positions in the vertex shader, window
// positions in the interpolation) and with the texture size (u, v
// normalized). At scale 0.3 a centre 1e-4 texel from a texel edge, 477
// pixels in, may show the texel on either side, depending on which
// triangle (overpaint's quad or a polygon's) covers it.
double texel_edge_tolerance(double gradient_x, double gradient_y, double x, double y, double size) {
    constexpr double ulps = 4.0 / 16777216; // 4 * 2^-24
    return std::max(kTexelEdgeTolerance, ulps * (std::abs(gradient_x) * std::abs(x) + std::abs(gradient_y) * std::abs(y) + size));
}

void check(runtime::Status status, const runtime::Renderer& r, const char* what) {
    if (status != runtime::Status::ok) throw Error(std::string("runtime renderer: ") + what + ": " + r.error());
}

} // namespace

std::int64_t count_off_texel_edges(ImageView a, ImageView b, const Scene& scene) {
    if (a.width != b.width || a.height != b.height) return std::int64_t(a.width) * a.height;
    std::vector<TexelMap> maps;
    for (const Element& e : scene.elements) maps.push_back(texel_map(e));
    std::int64_t count = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            if (std::equal(a.texel(x, y), a.texel(x, y) + 4, b.texel(x, y))) continue;
            const double sx = scene.viewport.x + x + 0.5, sy = scene.viewport.y + y + 0.5;
            bool explained = false;
            for (std::size_t k = 0; k < maps.size(); ++k) {
                const TexelMap& t = maps[k];
                const double u = t.u0 + t.ux * sx + t.uy * sy, v = t.v0 + t.vx * sx + t.vy * sy;
                const double tol = kTexelEdgeTolerance;
                if (u < t.rect.x - tol || v < t.rect.y - tol || u > t.rect.x + t.rect.w + tol || v > t.rect.y + t.rect.h + tol) continue;
                const SceneImage& img = scene.images[std::size_t(scene.elements[k].image)];
                // Coordinates: the larger of world and window, both summed by GL.
                const double cx = std::max(std::abs(sx), double(a.width)), cy = std::max(std::abs(sy), double(a.height));
                if (on_texel_edge(u, texel_edge_tolerance(t.ux, t.uy, cx, cy, img.width)) ||
                    on_texel_edge(v, texel_edge_tolerance(t.vx, t.vy, cx, cy, img.height))) {
                    explained = true;
                    break;
                }
            }
            count += explained ? 0 : 1;
        }
    return count;
}

RuntimeMeasurement measure_runtime(GlHost& host, const Scene& scene, const std::vector<ImageView>& images,
                                   const SceneAnalysis& analyses, const MeasureOptions& options) {
    host.make_current();
    RuntimeMeasurement out;
    out.width = scene.viewport.width;
    out.height = scene.viewport.height;
    out.ideal_overdraw = ideal_overdraw(scene, images).overdraw();
    std::vector<Mode> order{Mode::overpaint};
    for (Mode m : options.modes)
        if (std::find(order.begin(), order.end(), m) == order.end()) order.push_back(m);

    // One runtime renderer per mode, sharing the first one's textures, as
    // an engine would keep several scenes on one context.
    std::vector<std::unique_ptr<runtime::Renderer>> renderers;
    std::vector<ExcessStats> excess;
    for (std::size_t i = 0; i < order.size(); ++i) {
        std::string error;
        auto r = runtime::Renderer::create(&GlHost::get_proc_address, &error);
        if (!r) throw Error(error);
        if (i == 0) check(r->upload_images(images, scene.filter), *r, "textures");
        else check(r->set_textures(renderers[0]->texture_names()), *r, "textures");
        SceneMeshes meshes;
        ReconstructOptions reconstruct = options.reconstruct;
        reconstruct.coverage_margin = 0; // no rect test here: engine meshes
        if (ReconstructStatus s = build_meshes(order[i], scene, analyses, reconstruct, &meshes, true); s != ReconstructStatus::ok)
            throw Error(std::string(mode_name(order[i])) + " meshes: reconstruction failed");
        check(r->set_meshes(meshes), *r, "meshes");
        renderers.push_back(std::move(r));
        excess.push_back(excess_overdraw(meshes, images));
    }
    host.bind_framebuffer(out.width, out.height);
    const runtime::Camera camera = runtime::camera_of(scene.viewport, false);

    std::vector<RuntimeModeMeasurement> measured(order.size());
    Image reference;
    for (std::size_t i = 0; i < order.size(); ++i) {
        RuntimeModeMeasurement& m = measured[i];
        runtime::Renderer& r = *renderers[i];
        m.mode = order[i];
        m.excess = excess[i];
        runtime::FrameOptions counting;
        counting.clear_color = true;
        counting.count_samples = true;
        counting.no_depth_test = true;
        runtime::FrameCounts counts;
        check(r.draw(camera, {}, counting, &counts), r, "frame");
        m.fragments_rasterized = counts.samples_passed;
        counting.no_depth_test = false;
        check(r.draw(camera, {}, counting, &counts), r, "frame");
        m.fragments_shaded = counts.samples_passed;
        m.draw_calls = counts.draw_calls;
        m.triangles = counts.triangles;
        Image frame = host.read_pixels();
        if (i == 0) reference = frame;
        m.diff = compare_images(reference.view(), frame.view());
        if (m.diff.pixels_differ) m.off_texel_edges = count_off_texel_edges(reference.view(), frame.view(), scene);
        if (options.keep_frames) m.frame = std::move(frame);
    }

    // Modes take turns frame by frame, each round starting with a different
    // one, so load from others on a shared machine falls on every mode alike.
    if (options.frames > 0) {
        std::vector<std::vector<double>> wall(order.size()), cpu(order.size());
        runtime::FrameOptions plain;
        plain.clear_color = true;
        for (int round = -options.warmup; round < options.frames; ++round) {
            for (std::size_t k = 0; k < order.size(); ++k) {
                const std::size_t i = (std::size_t(round + options.warmup) + k) % order.size();
                runtime::FrameTimes t;
                check(renderers[i]->time_frames(camera, 1, plain, &t), *renderers[i], "timing");
                if (round >= 0) {
                    wall[i].push_back(t.wall_ms);
                    cpu[i].push_back(t.cpu_ms);
                }
            }
        }
        for (std::size_t i = 0; i < order.size(); ++i) {
            measured[i].wall_ms = median(wall[i]);
            measured[i].cpu_ms = median(cpu[i]);
        }
    }
    for (std::size_t i = 0; i < order.size(); ++i)
        if (std::find(options.modes.begin(), options.modes.end(), order[i]) != options.modes.end())
            out.modes.push_back(std::move(measured[i]));
    return out;
}

} // namespace depthcull::render
