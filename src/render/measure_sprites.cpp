// Moving sprites measured against what engines do today (issue 23;
// `depthcull bench --sprites N / --bunnymark N`). Every frame the same
// sprites are drawn three ways by depthcull::runtime, in turns (each frame
// starts with another mode, so load from elsewhere falls on all alike):
// - plain batching: what a sprite batcher does every frame: each element
//   on the camera as its rect, in painter's order, runs of one texture
//   and blend merged into one draw, no depth buffer;
// - meshes only: the static meshes reordered and batched once, the
//   sprites' boundary polygons batched by FrameAssembler, no opaque pass;
// - depth-culled: the same with opaque polygons drawn front to back with
//   depth writes first (static meshes with an insertion point reserving
//   the sprites' levels, FrameAssembler::assemble_at).
// The reference, untimed, is the overpaint of the same layers.
#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>

#include "depthcull/frame.h"
#include "depthcull/render.h"
#include "depthcull/runtime.h"

namespace depthcull::render {

namespace {

double cpu_now_ms() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

void check(runtime::Status status, const runtime::Renderer& r, const char* what) {
    if (status != runtime::Status::ok) throw Error(std::string("runtime renderer: ") + what + ": " + r.error());
}

// What a sprite can show: a scene element as a template (image, rect,
// colour, blend) and, when it is animated, each frame's image and rect.
struct Picture {
    std::vector<Element> frames; // frame 0 first; one for a still picture
    int id = -1;                 // FrameAssembler image id, or animation id when frames.size() > 1
};

// Whether e's rect, as placed, may touch the camera (a conservative box
// test, as a sprite batcher culls).
bool in_camera(const Element& e, const Viewport& v) {
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (const Vec2 c : {Vec2{0, 0}, Vec2{double(e.rect.w), 0}, Vec2{0, double(e.rect.h)}, Vec2{double(e.rect.w), double(e.rect.h)}}) {
        const Vec2 s = apply(e.transform, c);
        x0 = std::min(x0, s.x), y0 = std::min(y0, s.y), x1 = std::max(x1, s.x), y1 = std::max(y1, s.y);
    }
    return x1 >= v.x && y1 >= v.y && x0 <= v.x + v.width && y0 <= v.y + v.height;
}

// Plain sprite batching: e's rect as overpaint draws it (the same float
// vertices, so the same pixels), joining the last draw when that one has
// e's texture and blend.
void batch_quad(const Scene& scene, const Element& e, AssembledFrame& frame) {
    const SceneImage& img = scene.images[std::size_t(e.image)];
    const auto base = std::uint32_t(frame.vertices.size() / kVertexFloats);
    const Vec2 corners[4] = {{0, 0}, {double(e.rect.w), 0}, {double(e.rect.w), double(e.rect.h)}, {0, double(e.rect.h)}};
    for (const Vec2& c : corners) {
        const Vec2 s = apply(e.transform, c);
        const float v[kVertexFloats] = {float(s.x), float(s.y), 0.0f, float((e.rect.x + c.x) / img.width), float((e.rect.y + c.y) / img.height),
                                        e.color[0], e.color[1], e.color[2], e.color[3]};
        frame.vertices.insert(frame.vertices.end(), v, v + kVertexFloats);
    }
    if (frame.draws.empty() || frame.draws.back().image != e.image || frame.draws.back().blend != e.blend)
        frame.draws.push_back({e.image, Pass::blend, e.blend, std::uint32_t(frame.indices.size()), 0});
    for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) frame.indices.push_back(base + k);
    frame.draws.back().index_count += 6;
}

void start_batch(AssembledFrame& frame) {
    frame.vertices.clear();
    frame.indices.clear();
    frame.draws.clear();
    frame.opaque_draws = 0;
    frame.depth_test = false;
    frame.depth_denominator = 0;
}

void finish_batch(AssembledFrame& frame) {
    frame.points.assign(1, FramePoint{0, 0, std::uint32_t(frame.draws.size())});
    frame.stats = {};
    frame.stats.draw_calls = std::int64_t(frame.draws.size());
    frame.stats.triangles = std::int64_t(frame.indices.size() / 3);
}

// How each sprite moves: a fixed start from the seed, then a function of
// the frame number (map sprites) or one step per frame (bunnymark).
struct Motion {
    double x = 0, y = 0, vx = 0, vy = 0, angle = 0, spin = 0, scale = 1;
    double flip = 1;
    int phase = 0;
};

// --target for moving sprites: whether an opaque polygon of A texels
// (n vertices, perimeter P texels) pays in these frames on the profile.
// The cost model's terms (docs/cost-model.md): where it covers, the
// sprite's own blend fragments and those of the `layers` drawn behind it
// are rejected instead of shaded, and it writes A opaque fragments; it
// costs n - 2 triangles and their edges. Sprites are drawn at scales whose
// mean is `scale` and mean square `scale2`. min_opaque_area's rule for one
// layer behind, with the layers a crowd of sprites puts there.
bool opaque_polygon_pays(const CostProfile& p, const Polygon& polygon, double layers, double scale, double scale2) {
    double perimeter = 0;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
        const Vec2 a = polygon[i], b = polygon[(i + 1) % polygon.size()];
        perimeter += std::hypot(b.x - a.x, b.y - a.y);
    }
    const double gain_ns = area(polygon) * scale2 * ((layers + 1) * (p.fragment_blend_ns - p.fragment_rejected_ns) - p.fragment_opaque_ns);
    const double cost_ns = double(polygon.size() - 2) * p.triangle_us * 1e3 + 2 * perimeter * scale * p.triangle_perimeter_ns_per_pixel;
    return gain_ns > cost_ns;
}

} // namespace

const char* sprite_mode_name(SpriteMode mode) {
    switch (mode) {
    case SpriteMode::batching: return "plain batching";
    case SpriteMode::meshes: return "meshes only";
    case SpriteMode::culled: return "depth-culled";
    }
    return "";
}

SpriteMeasurement measure_sprites(GlHost& host, const Scene& scene, const std::vector<ImageView>& images, const SceneAnalysis& analysis,
                                  const SpriteBenchOptions& options) {
    if (options.sprites <= 0 || std::int64_t(options.sprites) > kMaxDepthLevels) throw Error("sprites: count outside 1.." + std::to_string(kMaxDepthLevels));
    host.make_current();
    SpriteMeasurement out;
    // The camera: the viewport's centre, at most max_width x max_height.
    const Viewport& whole = scene.viewport;
    const int w = std::min(options.max_width, whole.width), h = std::min(options.max_height, whole.height);
    if (w <= 0 || h <= 0) throw Error("sprites: the scene's viewport has no pixels");
    const Viewport camera{whole.x + std::round((whole.width - w) / 2.0), whole.y + std::round((whole.height - h) / 2.0), w, h};
    out.camera = camera;
    const std::size_t n = scene.elements.size();
    const std::size_t at = options.bunnymark ? 0 : scene.insertion_points.empty() ? n : scene.insertion_points[0];
    out.insertion_element = at;
    out.scene_point = !options.bunnymark && !scene.insertion_points.empty();

    // --target: the layers expected behind a sprite: the static elements
    // before the point over the camera, and half the sprites' own overdraw
    // (each over a random point of the pile; sprites show each distinct
    // picture alike).
    const double scale = options.bunnymark ? 1 : 1.125, scale2 = options.bunnymark ? 1 : (8 - 1 / 64.0) / (3 * 1.75); // uniform 0.25..2
    double layers = 0;
    if (options.target) {
        const double pixels = double(camera.width) * double(camera.height);
        double statics = 0, picture_area = 0, distinct = 0;
        std::vector<std::uint8_t> counted(analysis.images.size(), 0);
        for (std::size_t e = 0; e < n; ++e) {
            const Element& el = scene.elements[e];
            const double drawn = std::abs(el.transform[0] * el.transform[3] - el.transform[1] * el.transform[2]) * el.rect.w * el.rect.h;
            if (!options.bunnymark && e < at && in_camera(el, camera)) statics += std::min(drawn, pixels);
            if (analysis.of(e) && !counted[analysis.of_element[e]]) {
                counted[analysis.of_element[e]] = 1;
                picture_area += double(el.rect.w) * el.rect.h * scale2, distinct += 1;
            }
        }
        layers = statics / pixels + (distinct > 0 ? picture_area / distinct * options.sprites / pixels / 2 : 0);
    }
    out.layers_behind = layers;

    // ---- The pictures (load time): one per distinct analysis, animated
    // elements with every frame (their analysis covers all of them).
    AssemblerOptions culling, no_opaque;
    culling.filter = no_opaque.filter = scene.filter;
    no_opaque.opaque_pass = false;
    FrameAssembler culled(culling), meshes(no_opaque);
    std::vector<Picture> pictures;
    std::vector<std::uint8_t> seen(analysis.images.size(), 0);
    for (std::size_t e = 0; e < n; ++e) {
        const ImageAnalysis* a = analysis.of(e);
        if (!a || seen[analysis.of_element[e]]) continue;
        seen[analysis.of_element[e]] = 1;
        const Element& el = scene.elements[e];
        // --target: opaque polygons that do not pay on the profile are left out.
        ImageAnalysis kept = *a;
        if (options.target)
            std::erase_if(kept.opaque, [&](const Polygon& p) { return !opaque_polygon_pays(*options.target, p, layers, scale, scale2); });
        Picture picture;
        picture.frames.push_back(el);
        if (el.animation >= 0 && std::size_t(el.animation) < scene.animations.size()) {
            picture.frames.clear();
            for (const AnimationFrame& f : scene.animations[std::size_t(el.animation)].frames) {
                Element frame = el;
                frame.image = f.image, frame.rect = f.rect;
                picture.frames.push_back(frame);
            }
        }
        std::vector<int> ids[2];
        bool ok = true;
        for (const Element& f : picture.frames) {
            const SceneImage& img = scene.images[std::size_t(f.image)];
            // The analysis covers every frame in rect-relative texels (the
            // union of their texels, opaque only where all are): moved to
            // this frame's rect. Its bleeding edges were found for frame 0:
            // other frames draw their rect when turned, to be safe.
            ImageAnalysis frame = kept;
            const double dx = f.rect.x - kept.rect.x, dy = f.rect.y - kept.rect.y;
            for (std::vector<Polygon>* polygons : {&frame.boundary, &frame.opaque})
                for (Polygon& polygon : *polygons)
                    for (Vec2& v : polygon) v.x += dx, v.y += dy;
            frame.rect = f.rect;
            if (dx != 0 || dy != 0 || f.image != el.image) frame.bleeding_edges = true;
            int id_culled = -1, id_meshes = -1;
            ok = ok && culled.add_image({f.image, img.width, img.height, f.rect, &frame}, &id_culled) == FrameStatus::ok &&
                 meshes.add_image({f.image, img.width, img.height, f.rect, &frame}, &id_meshes) == FrameStatus::ok;
            ids[0].push_back(id_culled), ids[1].push_back(id_meshes);
        }
        if (!ok) continue;
        // Both assemblers number pictures and animations alike.
        picture.id = ids[0][0];
        if (picture.frames.size() > 1) {
            int animation = -1, same = -1;
            if (culled.add_animation(ids[0], &animation) != FrameStatus::ok || meshes.add_animation(ids[1], &same) != FrameStatus::ok) continue;
            picture.id = animation;
        }
        out.pictures_with_opaque += kept.opaque.empty() ? 0 : 1;
        pictures.push_back(std::move(picture));
    }
    out.pictures = pictures.size();
    if (pictures.empty()) throw Error("sprites: the scene has no pictures to show");

    // ---- The static meshes, reconstructed once for the camera with the
    // sprites' depth range reserved at the insertion point.
    Scene static_scene = scene;
    static_scene.viewport = camera;
    SceneMeshes culled_static, meshes_static;
    culled_static.viewport = meshes_static.viewport = camera;
    std::vector<Element> before, after; // static elements on the camera, behind and in front of the sprites
    if (!options.bunnymark) {
        ReconstructOptions ro;
        ro.cull_to_viewport = true;
        ro.insertion_points = {{at, options.sprites}};
        if (reconstruct_scene(static_scene, analysis, ro, &culled_static) != ReconstructStatus::ok)
            throw Error("sprites: the static meshes could not be reconstructed (depth levels)");
        ro.opaque_polygons = false;
        if (reconstruct_scene(static_scene, analysis, ro, &meshes_static) != ReconstructStatus::ok)
            throw Error("sprites: the static meshes could not be reconstructed (depth levels)");
        for (std::size_t e = 0; e < n; ++e)
            if (in_camera(scene.elements[e], camera)) (e < at ? before : after).push_back(scene.elements[e]);
        out.static_elements = before.size() + after.size();
    }
    out.static_draws[int(SpriteMode::meshes)] = std::int64_t(meshes_static.draws.size());
    out.static_draws[int(SpriteMode::culled)] = std::int64_t(culled_static.draws.size());

    // ---- Renderers: the reference and one per mode, sharing textures.
    std::unique_ptr<runtime::Renderer> renderers[4];
    for (int i = 0; i < 4; ++i) {
        std::string error;
        renderers[i] = runtime::Renderer::create(&GlHost::get_proc_address, &error);
        if (!renderers[i]) throw Error(error);
        if (i == 0) check(renderers[0]->upload_images(images, scene.filter), *renderers[0], "textures");
        else check(renderers[i]->set_textures(renderers[0]->texture_names()), *renderers[i], "textures");
    }
    runtime::Renderer& reference_renderer = *renderers[0];
    runtime::Renderer* mode_renderer[3] = {renderers[1].get(), renderers[2].get(), renderers[3].get()};
    SceneMeshes no_static;
    no_static.viewport = camera;
    check(mode_renderer[0]->set_meshes(no_static), *mode_renderer[0], "meshes");
    check(mode_renderer[1]->set_meshes(meshes_static), *mode_renderer[1], "meshes");
    check(mode_renderer[2]->set_meshes(culled_static), *mode_renderer[2], "meshes");
    host.bind_framebuffer(camera.width, camera.height);
    const runtime::Camera cam = runtime::camera_of(camera, false);

    // ---- The sprites, from the seed.
    std::mt19937 rng(options.seed);
    auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
    const std::size_t count = std::size_t(options.sprites);
    std::vector<Sprite> sprites(count);
    std::vector<Motion> motion(count);
    std::vector<std::size_t> picture_of(count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::size_t k = std::size_t(rng() % pictures.size());
        picture_of[i] = k;
        const Element& proto = pictures[k].frames[0];
        Sprite& s = sprites[i];
        if (pictures[k].frames.size() > 1) s.animation = pictures[k].id;
        else s.image = pictures[k].id;
        s.color = proto.color;
        s.blend = proto.blend;
        if (rng() % 4 == 0) s.color[0] *= 0.7f, s.color[2] *= 0.8f; // tinted
        Motion& m = motion[i];
        m.phase = int(rng() % 64);
        if (options.bunnymark) {
            // Bunnymark: dropped from the top half, falling and bouncing.
            m.x = uniform(camera.x, camera.x + camera.width), m.y = uniform(camera.y, camera.y + camera.height / 2.0);
            m.vx = uniform(-5, 5), m.vy = uniform(-2, 2);
        } else {
            m.x = uniform(camera.x - 32, camera.x + camera.width), m.y = uniform(camera.y - 32, camera.y + camera.height);
            m.vx = uniform(-3, 3), m.vy = uniform(-1.5, 1.5);
            m.angle = uniform(0, 6.283185307179586), m.spin = uniform(-0.05, 0.05), m.scale = uniform(0.25, 2);
            m.flip = rng() % 5 == 0 ? -1 : 1;
        }
    }
    auto place = [&](int f) {
        for (std::size_t i = 0; i < count; ++i) {
            Motion& m = motion[i];
            Sprite& s = sprites[i];
            s.frame = (f / 4 + m.phase);
            if (options.bunnymark) {
                m.vy += 0.5;
                m.x += m.vx, m.y += m.vy;
                const double right = camera.x + camera.width - 16, bottom = camera.y + camera.height - 16;
                if (m.x > right) m.vx = -m.vx, m.x = right;
                if (m.x < camera.x) m.vx = -m.vx, m.x = camera.x;
                if (m.y > bottom) {
                    m.vy *= -0.85, m.y = bottom;
                    if ((i + std::size_t(f)) % 2 == 0) m.vy -= 3 + double((i * 7 + std::size_t(f)) % 5);
                }
                if (m.y < camera.y) m.vy = 0, m.y = camera.y;
                s.transform = {1, 0, 0, 1, m.x, m.y};
            } else {
                // Wandering across the camera and back in.
                const double span_x = camera.width + 64.0, span_y = camera.height + 64.0;
                const double x = camera.x - 32 + std::fmod(std::fmod(m.x - camera.x + 32 + m.vx * f, span_x) + span_x, span_x);
                const double y = camera.y - 32 + std::fmod(std::fmod(m.y - camera.y + 32 + m.vy * f, span_y) + span_y, span_y);
                const double a = m.angle + m.spin * f, c = m.scale * std::cos(a), sn = m.scale * std::sin(a);
                s.transform = {m.flip * c, m.flip * sn, -sn, c, x, y};
            }
        }
    };
    // The element overpaint draws for sprite i (its current frame).
    auto element_of = [&](std::size_t i) {
        const Picture& p = pictures[picture_of[i]];
        const Sprite& s = sprites[i];
        Element e = p.frames[std::size_t(s.frame) % p.frames.size()];
        e.transform = s.transform;
        e.color = s.color;
        e.blend = s.blend;
        e.animation = -1;
        return e;
    };

    AssembledFrame frames[3];
    culled.reserve(count, &frames[2]);
    meshes.reserve(count, &frames[1]);
    Scene both = scene; // the reference: static and moving elements in layer order
    both.viewport = camera;
    both.insertion_points.clear();
    runtime::FrameOptions plain, counting;
    plain.clear_color = counting.clear_color = true;
    counting.count_samples = true;
    const std::span<const Sprite> lists[1] = {sprites};
    out.frames.resize(std::size_t(options.frames));
    for (int f = 0; f < options.frames; ++f) {
        place(f);
        both.elements = before;
        for (std::size_t i = 0; i < count; ++i) both.elements.push_back(element_of(i));
        both.elements.insert(both.elements.end(), after.begin(), after.end());
        check(reference_renderer.set_meshes(overpaint_meshes(both)), reference_renderer, "reference meshes");
        check(reference_renderer.draw(cam, {}, plain), reference_renderer, "reference frame");
        const Image reference = host.read_pixels();
        for (int k = 0; k < 3; ++k) {
            const auto mode = SpriteMode((f + k) % 3);
            const int m = int(mode);
            if (!options.modes[std::size_t(m)]) continue;
            runtime::Renderer& r = *mode_renderer[m];
            AssembledFrame& frame = frames[m];
            runtime::FrameCounts counts;
            const double start = cpu_now_ms();
            if (mode == SpriteMode::batching) {
                // What a sprite batcher does each frame: cull, quads, merge runs.
                start_batch(frame);
                for (const Element& e : before)
                    if (in_camera(e, camera)) batch_quad(scene, e, frame);
                for (std::size_t i = 0; i < count; ++i) {
                    const Element e = element_of(i);
                    if (in_camera(e, camera)) batch_quad(scene, e, frame);
                }
                for (const Element& e : after)
                    if (in_camera(e, camera)) batch_quad(scene, e, frame);
                finish_batch(frame);
            } else {
                FrameAssembler& assembler = mode == SpriteMode::culled ? culled : meshes;
                const SceneMeshes& statics = mode == SpriteMode::culled ? culled_static : meshes_static;
                const FrameStatus st = options.bunnymark ? assembler.assemble(sprites, camera, &frame) : assembler.assemble_at(statics, lists, camera, &frame);
                if (st != FrameStatus::ok) throw Error(std::string("sprites: ") + sprite_mode_name(mode) + ": frame assembly failed");
            }
            check(r.draw_frame(cam, frame, plain, &counts), r, "frame");
            host.finish();
            SpriteFrameMeasurement& row = out.frames[std::size_t(f)][std::size_t(m)];
            row.cpu_ms = cpu_now_ms() - start;
            row.draw_calls = counts.draw_calls;
            row.triangles = counts.triangles;
            // Fragments: counted in a second, untimed draw of the same frame.
            if (options.count_fragments) {
                check(r.draw_frame(cam, frame, counting, &counts), r, "counted frame");
                row.fragments_shaded = counts.samples_passed;
            }
            const Image drawn = host.read_pixels();
            row.pixels_differ = compare_images(reference.view(), drawn.view()).pixels_differ;
            if (row.pixels_differ) row.off_texel_edges = count_off_texel_edges(reference.view(), drawn.view(), both);
        }
    }
    return out;
}

std::string sprite_table(const SpriteMeasurement& m) {
    std::string out;
    char line[512];
    std::snprintf(line, sizeof line, "%5s |", "frame");
    out += line;
    for (int k = 0; k < 3; ++k) {
        std::snprintf(line, sizeof line, " %-46s |", sprite_mode_name(SpriteMode(k)));
        out += line;
    }
    out += "\n      |";
    for (int k = 0; k < 3; ++k) {
        std::snprintf(line, sizeof line, " %6s %8s %10s %8s %10s |", "draws", "tris", "fragments", "cpu ms", "diff/off");
        out += line;
    }
    out += "\n";
    SpriteFrameMeasurement sum[3];
    std::vector<double> cpu[3];
    for (std::size_t f = 0; f < m.frames.size(); ++f) {
        std::snprintf(line, sizeof line, "%5zu |", f);
        out += line;
        for (int k = 0; k < 3; ++k) {
            const SpriteFrameMeasurement& r = m.frames[f][std::size_t(k)];
            char diff[48];
            std::snprintf(diff, sizeof diff, "%" PRId64 "/%" PRId64, r.pixels_differ, r.off_texel_edges);
            std::snprintf(line, sizeof line, " %6" PRId64 " %8" PRId64 " %10" PRId64 " %8.2f %10s |", r.draw_calls, r.triangles, r.fragments_shaded, r.cpu_ms, diff);
            out += line;
            sum[k].draw_calls += r.draw_calls, sum[k].triangles += r.triangles, sum[k].fragments_shaded += r.fragments_shaded;
            sum[k].cpu_ms += r.cpu_ms, sum[k].pixels_differ += r.pixels_differ, sum[k].off_texel_edges += r.off_texel_edges;
            cpu[k].push_back(r.cpu_ms);
        }
        out += "\n";
    }
    const double frames = std::max<double>(1, double(m.frames.size()));
    out += " mean |";
    for (int k = 0; k < 3; ++k) {
        char diff[48];
        std::snprintf(diff, sizeof diff, "%.0f/%.0f", double(sum[k].pixels_differ) / frames, double(sum[k].off_texel_edges) / frames);
        std::snprintf(line, sizeof line, " %6.0f %8.0f %10.0f %8.2f %10s |", double(sum[k].draw_calls) / frames, double(sum[k].triangles) / frames,
                      double(sum[k].fragments_shaded) / frames, sum[k].cpu_ms / frames, diff);
        out += line;
    }
    out += "\n  med |";
    for (int k = 0; k < 3; ++k) {
        std::vector<double>& v = cpu[k];
        std::sort(v.begin(), v.end());
        const double median = v.empty() ? 0 : v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
        std::snprintf(line, sizeof line, " %6s %8s %10s %8.2f %10s |", "", "", "", median, "");
        out += line;
    }
    out += "\n";
    return out;
}

} // namespace depthcull::render
