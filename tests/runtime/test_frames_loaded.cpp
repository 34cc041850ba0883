// What a game does with our output (issue 23): load the meshes file the
// asset build wrote (JSON or binary), with its insertion points, and
// assemble moving sprites at them every frame. Each frame drawn by
// depthcull::runtime equals the overpaint of the static and moving
// elements in layer order, pixel for pixel.
#include <gtest/gtest.h>

#include <chrono>
#include <random>

#include "depthcull/frame.h"
#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "runtime_host.h"
#include "testing/corpus.h"

namespace depthcull {
namespace {

TEST(FramesFromFiles, SpritesAtTheLoadedInsertionPointsEqualOverpaint) {
    DEPTHCULL_RUNTIME_HOST(h, render::GlApi::desktop);
    pipeline::PreparedScene p = pipeline::prepare_scene(std::string(DEPTHCULL_SOURCE_DIR) + "/examples/meadow.json", {});
    const std::size_t n = p.scene.elements.size();
    ASSERT_GT(n, 40u);
    // Two points: a game layer in the middle and one near the top.
    const std::size_t at[2] = {n / 2, n - 10};
    ReconstructOptions options;
    options.insertion_points = {{at[0], 200}, {at[1], 50}};
    SceneMeshes built;
    ASSERT_EQ(reconstruct_scene(p.scene, p.analysis, options, &built), ReconstructStatus::ok);

    // The scene's own pictures, one per distinct analysis (load time).
    FrameAssembler assembler;
    std::vector<int> ids;
    std::vector<std::size_t> example; // an element showing each picture
    std::vector<std::uint8_t> seen(p.analysis.images.size(), 0);
    for (std::size_t e = 0; e < n; ++e) {
        const std::uint32_t a = p.analysis.of_element[e];
        if (seen[a]) continue;
        seen[a] = 1;
        const Element& el = p.scene.elements[e];
        const SceneImage& img = p.scene.images[std::size_t(el.image)];
        int id = -1;
        ASSERT_EQ(assembler.add_image({el.image, img.width, img.height, el.rect, &p.analysis.images[a]}, &id), FrameStatus::ok);
        ids.push_back(id);
        example.push_back(e);
    }
    const std::vector<ImageView> views = p.views();
    const Viewport view = p.scene.viewport;
    for (const bool binary : {false, true}) {
        const io::MeshesDocument loaded = binary ? io::meshes_from_binary(io::meshes_to_binary(io::meshes_document(p.scene, built), ""), "m.bin")
                                                 : io::meshes_from_json(io::meshes_to_json(io::meshes_document(p.scene, built), ""), "m.json");
        ASSERT_EQ(loaded.meshes.insertion_points, built.insertion_points);
        std::mt19937 rng(23);
        for (int f = 0; f < 4; ++f) {
            // Whole-pixel positions, scales 1 and 2, flips: no pixel centre
            // lies on a sprite's texel edge.
            std::vector<Sprite> lists[2];
            Scene both = p.scene;
            both.elements.clear();
            for (int k = 0; k < 2; ++k)
                for (int i = 0; i < (k ? 40 : 150); ++i) {
                    const std::size_t pick = rng() % ids.size();
                    const Element& el = p.scene.elements[example[pick]];
                    Sprite s;
                    s.image = ids[pick];
                    const double scale = rng() % 3 == 0 ? 2 : 1, flip = rng() % 2 ? -1 : 1;
                    s.transform = {flip * scale, 0, 0, scale, double(int(rng() % 700) - 30 + f * 7), double(int(rng() % 520) - 30)};
                    if (flip < 0) s.transform[4] += scale * el.rect.w;
                    s.color = el.color;
                    s.blend = el.blend;
                    if (rng() % 4 == 0) s.color = {0.8f, 0.6f, 1, 0.75f};
                    lists[k].push_back(s);
                }
            // Painter's order: the points' sprites before elements at[0], at[1].
            for (std::size_t e = 0; e <= n; ++e) {
                for (int k = 0; k < 2; ++k)
                    if (e == at[k])
                        for (const Sprite& s : lists[k]) {
                            Element el = p.scene.elements[example[std::size_t(std::find(ids.begin(), ids.end(), s.image) - ids.begin())]];
                            el.transform = s.transform, el.color = s.color, el.blend = s.blend, el.animation = -1;
                            both.elements.push_back(el);
                        }
                if (e < n) both.elements.push_back(p.scene.elements[e]);
            }
            const std::span<const Sprite> spans[2] = {lists[0], lists[1]};
            AssembledFrame frame;
            ASSERT_EQ(assembler.assemble_at(loaded.meshes, spans, view, &frame), FrameStatus::ok);
            EXPECT_GT(frame.stats.opaque_draws, 0);

            ASSERT_EQ(h->renderer->upload_images(views, Filter::nearest), runtime::Status::ok) << h->renderer->error();
            const Image reference = h->frame(overpaint_meshes(both));
            ASSERT_EQ(h->renderer->set_meshes(loaded.meshes), runtime::Status::ok) << h->renderer->error();
            h->host->bind_framebuffer(view.width, view.height);
            runtime::FrameOptions o;
            o.clear_color = true;
            ASSERT_EQ(h->renderer->draw_frame(runtime::camera_of(view, false), frame, o), runtime::Status::ok) << h->renderer->error();
            const Image drawn = h->host->read_pixels();
            // The sprites put no pixel centre on a texel edge; the meadow's
            // own rotated elements may (a centre exactly on a texel edge
            // may show either texel: render::count_off_texel_edges).
            const std::int64_t differ = render::compare_images(reference.view(), drawn.view()).pixels_differ;
            EXPECT_EQ(differ ? render::count_off_texel_edges(reference.view(), drawn.view(), both) : 0, 0)
                << (binary ? "binary" : "JSON") << " frame " << f << ": " << differ << " pixels differ";
            EXPECT_LE(differ, 1);
        }
    }
}

} // namespace
} // namespace depthcull

namespace depthcull {
namespace {

// Issue 23's acceptance, every frame: on every corpus map with an object
// layer, 1,000 of its own pictures (animated tiles playing their frames)
// moving in the first object layer for 60 frames,
// each frame equal to the overpaint of the same layers off texel edges,
// depth-culled as `bench --sprites` draws it. A 256x192 camera keeps it to
// a few seconds a map.
TEST(MovingSpritesCorpus, EveryMapWithAnObjectLayer1000Sprites60Frames) {
    std::unique_ptr<render::GlHost> host;
    try {
        host = render::GlHost::create({}, render::GlApi::desktop);
    } catch (const render::NoContext& e) {
        GTEST_SKIP() << e.what();
    }
    if (std::string missing = test::corpus_missing("tiled"); !missing.empty()) GTEST_SKIP() << missing;
    std::vector<std::string> paths = test::corpus_files("tiled", ".tmx");
    for (const std::string& q : test::corpus_files("tiled", ".tmx.gz")) paths.push_back(q);
    for (const std::string& q : test::corpus_files("btanks-data", ".tmx")) paths.push_back(q);
    int maps = 0;
    for (const std::string& path : paths) {
        pipeline::PreparedScene p;
        try {
            pipeline::PrepareOptions options;
            options.cache_dir = pipeline::default_cache_dir();
            p = pipeline::prepare_scene(path, options);
        } catch (const depthcull::Error&) {
            continue;
        }
        if (p.scene.insertion_points.empty() || p.scene.elements.empty()) continue;
        ++maps;
        render::SpriteBenchOptions options;
        options.sprites = 1000;
        options.frames = 60;
        options.max_width = 256, options.max_height = 192;
        // The depth-culled frames (bench --sprites checks all three);
        // sticker-knight's big sprites overdraw the camera about 95 times.
        options.modes = {false, false, true};
        options.count_fragments = false;
        const auto start = std::chrono::steady_clock::now();
        const render::SpriteMeasurement m = render::measure_sprites(*host, p.scene, p.views(), p.analysis, options);
        std::printf("  %s: %zu static elements on the camera, %.1f s\n", path.c_str(), m.static_elements,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        ASSERT_EQ(m.frames.size(), 60u);
        EXPECT_TRUE(m.scene_point);
        for (std::size_t f = 0; f < m.frames.size(); ++f)
            for (int k = 2; k < 3; ++k)
                EXPECT_EQ(m.frames[f][std::size_t(k)].off_texel_edges, 0)
                    << path << " frame " << f << " " << render::sprite_mode_name(render::SpriteMode(k)) << ": "
                    << m.frames[f][std::size_t(k)].pixels_differ << " pixels differ";
    }
    std::printf("%d corpus maps with an object layer: 1,000 moving sprites, 60 frames each, none off texel edges\n", maps);
}

} // namespace
} // namespace depthcull
