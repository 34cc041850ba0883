// Moving sprites depth-culled every frame (depthcull/frame.h) drawn by
// depthcull::runtime: fully dynamic frames and sprites at insertion points
// between a static scene's layers equal the runtime's own overpaint of the
// same elements in painter's order, pixel for pixel (only pixel centres
// exactly on a texel edge may differ: render::count_off_texel_edges).
#include <gtest/gtest.h>
#include <rapidcheck.h>

#include <cstdlib>
#include <random>

#include "../render/render_scenes.h"
#include "depthcull/frame.h"
#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "runtime_host.h"
#include "testing/corpus.h"

namespace depthcull {
namespace {

// A disc with a translucent rim and an opaque core big enough for opaque
// polygons; texel colours vary so a texel mix-up shows.
Image disc(int side) {
    Image img;
    img.width = img.height = side;
    img.rgba.resize(std::size_t(side) * std::size_t(side) * 4);
    const double c = side / 2.0, r = side / 2.0 - 1;
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x) {
            const double d = std::hypot(x + 0.5 - c, y + 0.5 - c);
            std::uint8_t* t = &img.rgba[(std::size_t(y) * std::size_t(side) + std::size_t(x)) * 4];
            t[0] = std::uint8_t(40 + 8 * x), t[1] = std::uint8_t(30 + 9 * y), t[2] = std::uint8_t((x * 7 + y * 13) % 256);
            t[3] = d < r - 2 ? 255 : d < r ? 128 : 0;
        }
    return img;
}

// Pictures for sprites: the test sprite, a ring, a solid block and two
// frames of an atlas page (an animation), each analysed once.
struct SpriteSet {
    test::RenderScene rs; // images only; elements added per frame
    std::vector<ImageAnalysis> analyses;
    std::vector<Rect> rects;
    std::vector<int> texture_of;
    FrameAssembler assembler;
    int animation = -1;

    explicit SpriteSet(const AssemblerOptions& options = {}) : assembler(options) {
        const int sprite = rs.add_image(test::test_sprite(), {});
        const int ring = rs.add_image(test::ascii_image({"..++++..", ".+####+.", "+######+", "+######+", ".+####+.", "..++++.."}), {});
        const int solid = rs.add_image(test::ascii_image({"####", "####", "####"}), {});
        const int page = rs.add_image(test::ascii_image({"########....++++", "########...+##++", "##....##..+####+",
                                                         "##....##..+####+", "########...+##+.", "########....++.."}),
                                      {});
        add(sprite, {0, 0, 12, 10});
        add(ring, {0, 0, 8, 6});
        const int ball = rs.add_image(disc(24), {});
        add(ball, {0, 0, 24, 24});
        add(solid, {0, 0, 4, 3});
        const int f0 = add(page, {0, 0, 8, 6});
        const int f1 = add(page, {8, 0, 8, 6});
        const int frames[2] = {f0, f1};
        EXPECT_EQ(assembler.add_animation(frames, &animation), FrameStatus::ok);
    }
    int add(int texture, Rect rect) {
        analyses.push_back(analyze_image(rs.images[std::size_t(texture)].view(), rect, {}));
        rects.push_back(rect);
        texture_of.push_back(texture);
        const Image& img = rs.images[std::size_t(texture)];
        int id = -1;
        EXPECT_EQ(assembler.add_image({texture, img.width, img.height, rect, &analyses.back()}, &id), FrameStatus::ok);
        return id;
    }
    // The element overpaint draws for sprite s.
    Element element(const Sprite& s) const {
        int picture = s.image;
        if (s.animation >= 0) picture = s.frame % 2 == 0 ? 4 : 5;
        Element e;
        e.image = texture_of[std::size_t(picture)];
        e.rect = rects[std::size_t(picture)];
        e.transform = s.transform;
        e.color = s.color;
        e.blend = s.blend;
        return e;
    }
};

Sprite random_sprite(std::mt19937& rng, const Viewport& v, int animation) {
    auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
    auto pick = [&](int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); };
    Sprite s;
    s.image = pick(4);
    if (pick(4) == 0) s.animation = animation, s.frame = pick(7);
    const double scale = pick(3) == 0 ? std::array<double, 4>{0.25, 0.5, 1, 2}[std::size_t(pick(4))] : uniform(0.25, 2);
    const double degrees = std::array<double, 4>{0, 90, 180, uniform(0, 360)}[std::size_t(pick(4))];
    // Off the pixel grid, as PixelIdentity.RandomScenes places them (see
    // FramesKnownIssue below for what whole-pixel positions still show).
    const double x = uniform(v.x - 10, v.x + v.width), y = uniform(v.y - 10, v.y + v.height);
    s.transform = test::rotation(degrees, x, y, scale);
    if (pick(4) == 0) s.transform[0] = -s.transform[0], s.transform[1] = -s.transform[1];
    s.blend = std::array<Blend, 6>{Blend::alpha, Blend::alpha, Blend::alpha, Blend::add, Blend::multiply, Blend::opaque}[std::size_t(pick(6))];
    if (pick(3) == 0) s.color = {float(uniform(0.3, 1)), float(uniform(0.3, 1)), float(uniform(0.3, 1)), pick(2) ? 1.0f : 0.6f};
    return s;
}

// Draws meshes + frame and the overpaint of `scene`; returns the pixels
// that differ off texel edges (and counts all that differ).
std::int64_t compare_with_overpaint(test::RuntimeHost& h, const Scene& scene, const std::vector<ImageView>& views,
                                    const SceneMeshes& static_meshes, const AssembledFrame& frame, std::int64_t* differ) {
    EXPECT_EQ(h.renderer->upload_images(views, Filter::nearest), runtime::Status::ok) << h.renderer->error();
    const Image reference = h.frame(overpaint_meshes(scene));
    EXPECT_EQ(h.renderer->set_meshes(static_meshes), runtime::Status::ok) << h.renderer->error();
    h.host->bind_framebuffer(scene.viewport.width, scene.viewport.height);
    runtime::FrameOptions options;
    options.clear_color = true;
    EXPECT_EQ(h.renderer->draw_frame(runtime::camera_of(scene.viewport, false), frame, options), runtime::Status::ok)
        << h.renderer->error();
    const Image drawn = h.host->read_pixels();
    const render::ImageDiff diff = render::compare_images(reference.view(), drawn.view());
    if (differ) *differ = diff.pixels_differ;
    return diff.pixels_differ ? render::count_off_texel_edges(reference.view(), drawn.view(), scene) : 0;
}

// The static reconstruction of the same scene, drawn by the runtime: its
// pixels off texel edges. The assembled frames use its very polygons, so
// a frame may differ only where it does (FramesKnownIssue below).
std::int64_t static_off(test::RuntimeHost& h, const Scene& scene, const std::vector<ImageView>& views, const SpriteSet& set) {
    SceneAnalysis analysis;
    for (const Element& e : scene.elements) {
        analysis.of_element.push_back(std::uint32_t(analysis.images.size()));
        analysis.images.push_back(analyze_image(set.rs.images[std::size_t(e.image)].view(), e.rect, {}));
    }
    SceneMeshes meshes;
    EXPECT_EQ(reconstruct_scene(scene, analysis, {}, &meshes), ReconstructStatus::ok);
    EXPECT_EQ(h.renderer->upload_images(views, Filter::nearest), runtime::Status::ok);
    const Image reference = h.frame(overpaint_meshes(scene));
    const Image drawn = h.frame(meshes);
    return render::count_off_texel_edges(reference.view(), drawn.view(), scene);
}

// The property both random frame tests check: the frame over `meshes`
// equals overpaint of `scene` off texel edges wherever the static
// reconstruction of the same elements does.
void check_frame_like_static(test::RuntimeHost& h, const Scene& scene, const std::vector<ImageView>& views, const SceneMeshes& meshes,
                             const AssembledFrame& frame, const SpriteSet& set) {
    std::int64_t differ = 0;
    const std::int64_t off = compare_with_overpaint(h, scene, views, meshes, frame, &differ);
    RC_CLASSIFY(off > 0, "differs where the static meshes differ too");
    if (off > 0) RC_ASSERT(static_off(h, scene, views, set) > 0);
}

class Frames : public testing::TestWithParam<render::GlApi> {};

// Property: any sprites (rotated, scaled 0.25-2, flipped, tinted, every
// blend mode, animated atlas frames) in a fully dynamic frame draw exactly
// like their overpaint.
TEST_P(Frames, FullyDynamicFramesEqualOverpaint) {
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    SpriteSet set;
    const auto views = set.rs.views();
    AssembledFrame frame;
    const bool ok = rc::check("fully dynamic frame == overpaint", [&] {
        std::mt19937 rng(*rc::gen::arbitrary<unsigned>());
        const int count = *rc::gen::inRange(1, 120);
        Scene scene = set.rs.scene;
        scene.viewport = {-7.5 + *rc::gen::inRange(0, 4), 3, 96, 72};
        std::vector<Sprite> sprites;
        for (int i = 0; i < count; ++i) sprites.push_back(random_sprite(rng, scene.viewport, set.animation));
        for (const Sprite& s : sprites) scene.elements.push_back(set.element(s));
        RC_ASSERT(set.assembler.assemble(sprites, scene.viewport, &frame) == FrameStatus::ok);
        SceneMeshes none;
        none.viewport = scene.viewport;
        check_frame_like_static(*h, scene, views, none, frame, set);
    });
    EXPECT_TRUE(ok);
}

// Property, the templates' fast paths (issue 23): convex polygons drawn
// dilated with their skirt, joined skirts, and the wider texel-margin
// templates of sprites scaled below 1/8 (down to 1/64, stretched along one
// axis, flipped, turned, snapped to whole pixels or not) draw exactly like
// their overpaint wherever the static reconstruction of the same elements
// (exact per-element margin) does.
TEST_P(Frames, TinyStretchedAndFlippedSpritesEqualOverpaint) {
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    SpriteSet set;
    const auto views = set.rs.views();
    AssembledFrame frame;
    const bool ok = rc::check("tiny, stretched, flipped sprites == overpaint", [&] {
        std::mt19937 rng(*rc::gen::arbitrary<unsigned>());
        auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
        const int count = *rc::gen::inRange(1, 150);
        Scene scene = set.rs.scene;
        scene.viewport = {-2.5, 1, 64, 48};
        std::vector<Sprite> sprites;
        for (int i = 0; i < count; ++i) {
            Sprite s = random_sprite(rng, scene.viewport, set.animation);
            const double sx = std::exp2(uniform(-6, 1)), sy = rng() % 3 == 0 ? std::exp2(uniform(-6, 1)) : sx;
            const double a = rng() % 4 == 0 ? 0.0 : uniform(0, 6.2832);
            const double x = rng() % 4 == 0 ? std::floor(s.transform[4]) : s.transform[4];
            s.transform = {sx * std::cos(a), sx * std::sin(a), -sy * std::sin(a), sy * std::cos(a), x, s.transform[5]};
            if (rng() % 3 == 0) s.transform[0] = -s.transform[0], s.transform[1] = -s.transform[1];
            sprites.push_back(s);
            scene.elements.push_back(set.element(s));
        }
        RC_ASSERT(set.assembler.assemble(sprites, scene.viewport, &frame) == FrameStatus::ok);
        SceneMeshes none;
        none.viewport = scene.viewport;
        check_frame_like_static(*h, scene, views, none, frame, set);
    });
    EXPECT_TRUE(ok);
}

// Many overlapping sprites of two textures: the blend pass batches them
// (fewer draws than sprites) and the frame still equals overpaint.
TEST_P(Frames, OverlappingSpritesBatchAndStayIdentical) {
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    SpriteSet set;
    std::mt19937 rng(7);
    Scene scene = set.rs.scene;
    scene.viewport = {0, 0, 128, 96};
    std::vector<Sprite> sprites;
    for (int i = 0; i < 400; ++i) {
        Sprite s = random_sprite(rng, scene.viewport, set.animation);
        s.image = 1 + i % 2, s.animation = -1, s.blend = Blend::alpha;
        sprites.push_back(s);
        scene.elements.push_back(set.element(s));
    }
    AssembledFrame frame;
    ASSERT_EQ(set.assembler.assemble(sprites, scene.viewport, &frame), FrameStatus::ok);
    EXPECT_LT(frame.stats.blend_batches, 200);
    EXPECT_GT(frame.stats.opaque_draws, 0);
    SceneMeshes none;
    none.viewport = scene.viewport;
    std::int64_t differ = 0;
    EXPECT_EQ(compare_with_overpaint(*h, scene, set.rs.views(), none, frame, &differ), 0) << differ << " pixels differ";
}

// Property: sprites at insertion points between the layers of a static
// scene (the static scene reconstructed with reserved depth ranges) equal
// the overpaint of static and moving elements in layer order.
TEST_P(Frames, SpritesAtInsertionPointsEqualOverpaint) {
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    SpriteSet set;
    const auto views = set.rs.views();
    AssembledFrame frame;
    const bool ok = rc::check("insertion points == overpaint", [&] {
        std::mt19937 rng(*rc::gen::arbitrary<unsigned>());
        Scene base = set.rs.scene;
        base.viewport = {-3, 5, 96, 72};
        // The static layers: a background, then sprites (static).
        std::vector<Element> statics;
        Element bg;
        bg.image = 2, bg.rect = {0, 0, 4, 3}, bg.transform = {24, 0, 0, 24, -3, 5}, bg.blend = Blend::alpha;
        statics.push_back(bg);
        const int n_static = *rc::gen::inRange(0, 60);
        for (int i = 0; i < n_static; ++i) statics.push_back(set.element(random_sprite(rng, base.viewport, set.animation)));
        // Points at ascending element indices.
        const int n_points = *rc::gen::inRange(1, 4);
        std::vector<std::size_t> at;
        for (int k = 0; k < n_points; ++k) at.push_back(std::size_t(*rc::gen::inRange(0, int(statics.size()) + 1)));
        std::sort(at.begin(), at.end());
        std::vector<std::vector<Sprite>> moving(static_cast<std::size_t>(n_points));
        for (auto& list : moving) {
            const int count = *rc::gen::inRange(0, 30);
            for (int i = 0; i < count; ++i) list.push_back(random_sprite(rng, base.viewport, set.animation));
        }
        Scene static_scene = base, whole = base;
        static_scene.elements = statics;
        SceneAnalysis analysis;
        for (const Element& e : statics) {
            analysis.of_element.push_back(std::uint32_t(analysis.images.size()));
            analysis.images.push_back(analyze_image(set.rs.images[std::size_t(e.image)].view(), e.rect, {}));
        }
        ReconstructOptions options;
        for (std::size_t p : at) options.insertion_points.push_back({p, 30});
        SceneMeshes meshes;
        RC_ASSERT(reconstruct_scene(static_scene, analysis, options, &meshes) == ReconstructStatus::ok);
        RC_ASSERT(meshes.insertion_points.size() == at.size());
        // Painter's order: statics with each point's sprites before element at[k].
        std::size_t next = 0;
        for (std::size_t i = 0; i <= statics.size(); ++i) {
            for (; next < at.size() && at[next] == i; ++next)
                for (const Sprite& s : moving[next]) whole.elements.push_back(set.element(s));
            if (i < statics.size()) whole.elements.push_back(statics[i]);
        }
        std::vector<std::span<const Sprite>> lists(moving.begin(), moving.end());
        RC_ASSERT(set.assembler.assemble_at(meshes, lists, base.viewport, &frame) == FrameStatus::ok);
        check_frame_like_static(*h, whole, views, meshes, frame, set);
    });
    EXPECT_TRUE(ok);
}

// Issue 23's acceptance: every corpus map with an object layer, 1,000 of
// its own pictures moving in the (first) object layer for 60 frames, each
// frame equal to the overpaint of static and moving elements in layer
// order. CI draws every 20th frame; DEPTHCULL_FULL_FRAMES=1 draws all 60.
TEST_P(Frames, CorpusMapsWithMovingSpritesInTheGameLayer) {
    if (GetParam() == render::GlApi::gles) GTEST_SKIP() << "corpus frames are drawn on desktop GL only";
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    const bool full = std::getenv("DEPTHCULL_FULL_FRAMES") != nullptr;
    int maps = 0, frames_drawn = 0, frames_like_static = 0;
    for (const char* package : {"tiled", "btanks-data"}) {
        if (std::string why = test::corpus_missing(package); !why.empty()) GTEST_SKIP() << why;
        std::vector<std::string> paths = test::corpus_files(package, ".tmx");
        for (const std::string& q : test::corpus_files(package, ".tmx.gz")) paths.push_back(q);
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
            const Viewport whole = p.scene.viewport;
            const int w = std::min(1024, whole.width), hgt = std::min(768, whole.height);
            const Viewport view{whole.x + std::round((whole.width - w) / 2.0), whole.y + std::round((whole.height - hgt) / 2.0), w, hgt};
            p.scene.viewport = view;
            const std::size_t at = p.scene.insertion_points[0];
            ReconstructOptions options;
            options.insertion_points = {{at, 1000}};
            SceneMeshes meshes;
            ASSERT_EQ(reconstruct_scene(p.scene, p.analysis, options, &meshes), ReconstructStatus::ok) << path;
            // The scene's own pictures: one per distinct analysis.
            FrameAssembler assembler;
            std::vector<int> picture_element;
            std::vector<int> ids;
            std::vector<std::uint8_t> seen(p.analysis.images.size(), 0);
            for (std::size_t e = 0; e < p.scene.elements.size(); ++e) {
                const std::uint32_t a = p.analysis.of_element[e];
                if (seen[a]) continue;
                seen[a] = 1;
                const Element& el = p.scene.elements[e];
                const SceneImage& img = p.scene.images[std::size_t(el.image)];
                int id = -1;
                ASSERT_EQ(assembler.add_image({el.image, img.width, img.height, el.rect, &p.analysis.images[a]}, &id), FrameStatus::ok);
                ids.push_back(id);
                picture_element.push_back(int(e));
            }
            std::mt19937 rng(23);
            auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
            std::vector<Sprite> sprites(1000);
            std::vector<std::array<double, 4>> motion; // x, y, angle, scale
            std::vector<double> speed;
            for (Sprite& sp : sprites) {
                const std::size_t k = std::size_t(rng() % ids.size());
                const Element& el = p.scene.elements[std::size_t(picture_element[k])];
                sp.image = ids[k];
                sp.color = el.color;
                sp.blend = el.blend;
                motion.push_back({uniform(view.x - 32, view.x + view.width), uniform(view.y - 32, view.y + view.height), uniform(0, 6.283),
                                  uniform(0.25, 2)});
                if (rng() % 4 == 0) sp.color[0] *= 0.7f, sp.color[2] *= 0.8f; // tinted
                speed.push_back(uniform(-3, 3));
            }
            const std::vector<ImageView> views = p.views();
            AssembledFrame frame;
            for (int f = 0; f < 60; ++f) {
                for (std::size_t i = 0; i < sprites.size(); ++i) {
                    auto& m = motion[i];
                    const double a = m[2] + 0.05 * f * speed[i], x = m[0] + f * speed[i], y = m[1] + 0.5 * f * speed[i];
                    const double flip = i % 5 == 0 ? -1 : 1;
                    sprites[i].transform = {flip * m[3] * std::cos(a), flip * m[3] * std::sin(a), -m[3] * std::sin(a), m[3] * std::cos(a), x, y};
                }
                if (!full && f % 20 != 0) continue;
                std::vector<std::span<const Sprite>> lists{sprites};
                ASSERT_EQ(assembler.assemble_at(meshes, lists, view, &frame), FrameStatus::ok) << path;
                Scene both = p.scene;
                both.elements.assign(p.scene.elements.begin(), p.scene.elements.begin() + std::ptrdiff_t(at));
                for (std::size_t i = 0; i < sprites.size(); ++i) {
                    const Element& src = p.scene.elements[std::size_t(picture_element[std::size_t(sprites[i].image)])];
                    Element e = src;
                    e.transform = sprites[i].transform;
                    e.color = sprites[i].color;
                    e.animation = -1;
                    both.elements.push_back(e);
                }
                both.elements.insert(both.elements.end(), p.scene.elements.begin() + std::ptrdiff_t(at), p.scene.elements.end());
                std::int64_t differ = 0;
                const std::int64_t off = compare_with_overpaint(*h, both, views, meshes, frame, &differ);
                // Frames may differ only where the static reconstruction of
                // the very same elements does (FramesKnownIssue: pixel centres
                // off texel edges under arbitrary turns and scales).
                std::int64_t static_differs = 0;
                if (off) {
                    SceneAnalysis sa;
                    sa.images = p.analysis.images;
                    for (std::size_t e = 0; e < at; ++e) sa.of_element.push_back(p.analysis.of_element[e]);
                    for (const Sprite& sp : sprites)
                        sa.of_element.push_back(p.analysis.of_element[std::size_t(picture_element[std::size_t(sp.image)])]);
                    for (std::size_t e = at; e < p.scene.elements.size(); ++e) sa.of_element.push_back(p.analysis.of_element[e]);
                    SceneMeshes rec;
                    ASSERT_EQ(reconstruct_scene(both, sa, {}, &rec), ReconstructStatus::ok);
                    const Image ref = h->frame(overpaint_meshes(both));
                    const Image got = h->frame(rec);
                    static_differs = render::count_off_texel_edges(ref.view(), got.view(), both);
                    ++frames_like_static;
                }
                EXPECT_LE(off, static_differs) << path << " frame " << f << ": " << differ << " pixels differ, " << off
                                               << " off texel edges (static reconstruction: " << static_differs << ")";
                ++frames_drawn;
            }
        }
    }
    std::printf("%d maps with an object layer, %d frames of 1,000 moving sprites compared; %d with pixels off texel edges, none more than the static reconstruction of the same elements\n",
                maps, frames_drawn, frames_like_static);
}

INSTANTIATE_TEST_SUITE_P(Targets, Frames, testing::Values(render::GlApi::desktop, render::GlApi::gles),
                         [](const auto& info) { return info.param == render::GlApi::gles ? "es30" : "gl33"; });

} // namespace
} // namespace depthcull
namespace depthcull {
namespace {

// Found while writing the frame tests, not caused by them: a ring with a
// transparent hole, alone, rotated off the axes, drawn by the static
// reconstruction (reconstruct_scene, texel margin) in the runtime differs
// from overpaint in one pixel off any texel edge. Both draw like overpaint
// as of main 435ce5b (issue 21 point 3): kept as regression tests.
TEST(FramesKnownIssue, RotatedRingWithAHoleStatic) {
    DEPTHCULL_RUNTIME_HOST(h, render::GlApi::desktop);
    test::RenderScene rs;
    rs.scene.viewport = {-7.5, 3, 96, 72};
    rs.add_image(test::ascii_image({"..++++..", ".+####+.", "+##..##+", "+##..##+", ".+####+.", "..++++.."}), {});
    rs.add(0, {0.32563148451449364, -0.37942606169435311, -0.37942606169435311, -0.32563148451449364, 74.779112007781151,
               19.168002944186387});
    SceneAnalysis analysis;
    analysis.of_element = {0};
    analysis.images.push_back(analyze_image(rs.images[0].view(), rs.scene.elements[0].rect, {}));
    SceneMeshes meshes;
    ASSERT_EQ(reconstruct_scene(rs.scene, analysis, {}, &meshes), ReconstructStatus::ok);
    ASSERT_EQ(h->renderer->upload_images(rs.views(), Filter::nearest), runtime::Status::ok);
    const Image reference = h->frame(overpaint_meshes(rs.scene));
    const Image drawn = h->frame(meshes);
    EXPECT_EQ(render::count_off_texel_edges(reference.view(), drawn.view(), rs.scene), 0);
}

// The same with the disc of SpriteSet (no hole), turned and scaled about
// 0.31, at a whole-pixel y: one pixel off any texel edge, static meshes.
TEST(FramesKnownIssue, RotatedDiscAtAWholePixelStatic) {
    DEPTHCULL_RUNTIME_HOST(h, render::GlApi::desktop);
    test::RenderScene rs;
    rs.scene.viewport = {-7.5, 3, 96, 72};
    rs.add_image(disc(24), {});
    rs.add(0, {-0.29967186063173701, -0.08611216227789277, 0.08611216227789277, -0.29967186063173701, 77.870815799673835, 68});
    SceneAnalysis analysis;
    analysis.of_element = {0};
    analysis.images.push_back(analyze_image(rs.images[0].view(), rs.scene.elements[0].rect, {}));
    SceneMeshes meshes;
    ASSERT_EQ(reconstruct_scene(rs.scene, analysis, {}, &meshes), ReconstructStatus::ok);
    ASSERT_EQ(h->renderer->upload_images(rs.views(), Filter::nearest), runtime::Status::ok);
    const Image reference = h->frame(overpaint_meshes(rs.scene));
    const Image drawn = h->frame(meshes);
    EXPECT_EQ(render::count_off_texel_edges(reference.view(), drawn.view(), rs.scene), 0);
}

} // namespace
} // namespace depthcull
