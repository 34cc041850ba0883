// What a game does with our output (issue 23): load the meshes file the
// asset build wrote (JSON or binary), with its insertion points, and
// assemble moving sprites at them every frame. Each frame drawn by
// depthcull::runtime equals the overpaint of the static and moving
// elements in layer order, pixel for pixel.
#include <gtest/gtest.h>

#include <random>

#include "depthcull/frame.h"
#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "runtime_host.h"

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
        const io::LoadedMeshes loaded = binary ? io::meshes_from_binary(io::meshes_to_binary(p.scene, built, ""), "m.bin")
                                               : io::meshes_from_json(io::meshes_to_json(p.scene, built, ""), "m.json");
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
