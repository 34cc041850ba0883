// The GL renderer: optimized output draws pixel for pixel like overpaint,
// and GL_SAMPLES_PASSED agrees with the CPU analyzer. Skips, with the
// reason, where no OpenGL context can be made.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>

#include "depthcull/overdraw.h"
#include "depthcull/render.h"
#include "render_scenes.h"
#include "shared_renderer.h"

namespace depthcull {
namespace {

#define REQUIRE_GL(r)                                                                                                      \
    std::string why_no_gl;                                                                                                 \
    bool no_gl_context = false;                                                                                            \
    render::GlRenderer* r = test::shared_renderer(&why_no_gl, &no_gl_context);                                             \
    if (!r && no_gl_context) GTEST_SKIP() << why_no_gl;                                                                    \
    if (!r) FAIL() << why_no_gl

// maps: element_maps of the scene the meshes' element spans name.
Image draw(render::GlRenderer& r, const SceneMeshes& meshes, render::FrameCounts* counts = nullptr,
           const std::vector<TexelMap>& maps = {}) {
    r.set_meshes(meshes, maps);
    render::FrameCounts c = r.draw_counted();
    if (counts) *counts = c;
    return r.read_pixels();
}

TEST(GlRender, OptimizedEqualsOverpaintPixelForPixel) {
    REQUIRE_GL(r);
    auto rs = test::mixed_scene();
    r->set_images(rs.views(), Filter::nearest);
    Image over = draw(*r, overpaint_meshes(rs.scene, 0, true), nullptr, element_maps(rs.scene));
    Image opt = draw(*r, test::hand_optimized(rs), nullptr, element_maps(rs.scene));
    auto diff = render::compare_images(over.view(), opt.view());
    EXPECT_EQ(diff.pixels_differ, 0) << "max channel difference " << diff.max_channel_diff;
    // The scene really draws something everywhere the background is.
    std::int64_t blank = 0;
    for (std::size_t i = 3; i < over.rgba.size(); i += 4) blank += over.rgba[i] == 0;
    EXPECT_EQ(blank, 0);
}

// Meshes read from a file carry no element maps; the renderer then solves
// each triangle's map from its vertices. On this scene (no vertex far from
// the origin) that still draws exactly like overpaint.
TEST(GlRender, MeshesWithoutElementMapsDrawLikeOverpaint) {
    REQUIRE_GL(r);
    auto rs = test::mixed_scene();
    r->set_images(rs.views(), Filter::nearest);
    Image over = draw(*r, overpaint_meshes(rs.scene, 0, true), nullptr, element_maps(rs.scene));
    Image bare_over = draw(*r, test::without_element_maps(overpaint_meshes(rs.scene, 0, true)), nullptr, element_maps(rs.scene));
    Image bare_opt = draw(*r, test::without_element_maps(test::hand_optimized(rs)), nullptr, element_maps(rs.scene));
    EXPECT_EQ(render::compare_images(over.view(), bare_over.view()).pixels_differ, 0);
    EXPECT_EQ(render::compare_images(over.view(), bare_opt.view()).pixels_differ, 0);
}

TEST(GlRender, LinearFilteringDifferenceIsReported) {
    REQUIRE_GL(r);
    auto rs = test::mixed_scene();
    r->set_images(rs.views(), Filter::linear);
    Image over = draw(*r, overpaint_meshes(rs.scene, 0, true), nullptr, element_maps(rs.scene));
    Image opt = draw(*r, test::hand_optimized(rs), nullptr, element_maps(rs.scene));
    auto diff = render::compare_images(over.view(), opt.view());
    // The hand-made opaque quads cover the opaque core up to its edge, where
    // bilinear filtering already mixes in translucent texels: differences
    // are expected there, and only there (a quarter-texel band).
    RecordProperty("linear_max_channel_diff", diff.max_channel_diff);
    RecordProperty("linear_pixels_differ", int(diff.pixels_differ));
    EXPECT_LT(diff.pixels_differ, over.width * over.height / 4);
    r->set_images(rs.views(), Filter::nearest);
}

TEST(GlRender, SamplesPassedMatchesTheCpuAnalyzer) {
    REQUIRE_GL(r);
    auto rs = test::mixed_scene();
    r->set_images(rs.views(), Filter::nearest);
    for (const SceneMeshes& m : {overpaint_meshes(rs.scene, 0, true), test::hand_optimized(rs)}) {
        render::FrameCounts counts;
        draw(*r, m, &counts, element_maps(rs.scene));
        auto cpu = analyze_overdraw(m);
        EXPECT_EQ(counts.samples_passed, cpu.shaded) << (m.depth_test ? "optimized" : "overpaint");
        EXPECT_EQ(counts.draw_calls, std::int64_t(m.draws.size()));
    }
}

TEST(GlRender, FillRuleMatchesTheCpuAnalyzerOnAwkwardTriangles) {
    REQUIRE_GL(r);
    test::RenderScene rs;
    rs.add_image(test::ascii_image({"#"}), {});
    r->set_images(rs.views(), Filter::nearest);
    // Vertices on pixel centres, pixel corners, and the 1/256 subpixel grid:
    // edges through pixel centres in every direction. Inside the viewport
    // only: GL clips triangles that cross its edge, computing new vertices
    // in float, and then a centre exactly on a clipped edge may fall either
    // way (measured: about 1 pixel in 1000 for these random triangles).
    std::mt19937 rng(7);
    for (int grid : {2, 256}) {
        SceneMeshes m;
        m.viewport = {0, 0, 24, 20};
        Draw d;
        std::uniform_int_distribution<int> x(0, 24 * grid), y(0, 20 * grid);
        for (int i = 0; i < 300; ++i)
            d.vertices.insert(d.vertices.end(), {float(x(rng)) / float(grid), float(y(rng)) / float(grid), 0, 0, 0, 1, 1, 1, 1});
        for (std::uint32_t i = 0; i + 2 < 300; i += 3) d.indices.insert(d.indices.end(), {i, i + 1, i + 2});
        m.draws.push_back(d);
        render::FrameCounts counts;
        draw(*r, m, &counts, element_maps(rs.scene));
        EXPECT_EQ(counts.samples_passed, analyze_overdraw(m).shaded) << "grid 1/" << grid;
    }
}

TEST(GlRender, BlendModesWriteWhatSceneHSays) {
    REQUIRE_GL(r);
    test::RenderScene rs;
    rs.scene.viewport = {0, 0, 4, 1};
    Image white;
    white.width = 1;
    white.height = 1;
    white.rgba = {200, 100, 50, 128};
    const int img = rs.add_image(std::move(white), {});
    Image grey = test::ascii_image({"#"});
    grey.rgba = {100, 100, 100, 255};
    const int bg = rs.add_image(std::move(grey), {0, 0, 1, 1});
    rs.add(bg, {4, 0, 0, 1, 0, 0});
    rs.add(img, {1, 0, 0, 1, 0, 0}, Blend::alpha);
    rs.add(img, {1, 0, 0, 1, 1, 0}, Blend::add);
    rs.add(img, {1, 0, 0, 1, 2, 0}, Blend::multiply);
    rs.add(img, {1, 0, 0, 1, 3, 0}, Blend::opaque);
    r->set_images(rs.views(), Filter::nearest);
    Image f = draw(*r, overpaint_meshes(rs.scene, 0, true), nullptr, element_maps(rs.scene));
    auto px = [&](int x, int c) { return int(f.rgba[std::size_t(x) * 4 + std::size_t(c)]); };
    const double a = 128 / 255.0;
    EXPECT_NEAR(px(0, 0), 200 * a + 100 * (1 - a), 1);                // alpha
    EXPECT_NEAR(px(1, 0), std::min(255.0, 200 * a + 100), 1);          // add
    EXPECT_NEAR(px(2, 0), 200 * a * 100 / 255.0 + 100 * (1 - a), 1);  // multiply
    EXPECT_EQ(px(3, 0), 200);                                          // opaque: alpha ignored
    EXPECT_EQ(px(3, 3), 255);
}

TEST(GlRender, MeshesOnlyAndReconstructionDrawLikeOverpaint) {
    REQUIRE_GL(r);
    auto rs = test::mixed_scene();
    r->set_images(rs.views(), Filter::nearest);
    Image over = draw(*r, overpaint_meshes(rs.scene, 0, true), nullptr, element_maps(rs.scene));

    SceneMeshes meshes;
    ReconstructOptions spanned;
    spanned.element_spans = true;
    ASSERT_EQ(rectangle_meshes(rs.scene, spanned, &meshes), ReconstructStatus::ok);
    auto d1 = render::compare_images(over.view(), draw(*r, meshes, nullptr, element_maps(rs.scene)).view());
    EXPECT_EQ(d1.pixels_differ, 0) << "meshes only, max channel difference " << d1.max_channel_diff;

    // The real paper 2.3 output over the real per-image analysis.
    std::vector<ImageAnalysis> analyses;
    analyses.reserve(rs.scene.elements.size());
    std::vector<const ImageAnalysis*> per_element;
    for (const Element& e : rs.scene.elements) {
        analyses.push_back(analyze_image(rs.images[std::size_t(e.image)].view(), e.rect, {}));
        per_element.push_back(&analyses.back());
    }
    SceneMeshes optimized;
    ASSERT_EQ(reconstruct_scene(rs.scene, per_element, spanned, &optimized), ReconstructStatus::ok);
    auto d2 = render::compare_images(over.view(), draw(*r, optimized, nullptr, element_maps(rs.scene)).view());
    EXPECT_EQ(d2.pixels_differ, 0) << "reconstruct_scene, max channel difference " << d2.max_channel_diff;
}

} // namespace
} // namespace depthcull

namespace depthcull {
namespace {

TEST(GlRender, MeshSlotsDrawWhatSetMeshesDraws) {
    REQUIRE_GL(r);
    auto rs = test::mixed_scene();
    r->set_images(rs.views(), Filter::nearest);
    const SceneMeshes over = overpaint_meshes(rs.scene, 0, true), opt = test::hand_optimized(rs);
    const Image over_frame = draw(*r, over, nullptr, element_maps(rs.scene)), opt_frame = draw(*r, opt, nullptr, element_maps(rs.scene));
    r->set_meshes(over, element_maps(rs.scene));
    const int slot = r->add_meshes(opt, element_maps(rs.scene));
    for (int round = 0; round < 2; ++round) {
        r->select_meshes(0);
        r->draw();
        EXPECT_EQ(r->read_pixels().rgba, over_frame.rgba);
        r->select_meshes(slot);
        r->time_frame(); // draws the selected slot as draw() does: the pixels below say so
        EXPECT_EQ(r->read_pixels().rgba, opt_frame.rgba);
    }
}

TEST(MeasureScene, TableTwoRowsForEveryMode) {
    REQUIRE_GL(r);
    auto rs = test::mixed_scene();
    SceneAnalysis analysis; // one per element
    for (const Element& e : rs.scene.elements) {
        analysis.of_element.push_back(std::uint32_t(analysis.images.size()));
        analysis.images.push_back(analyze_image(rs.images[std::size_t(e.image)].view(), e.rect, {}));
    }
    render::MeasureOptions options;
    options.frames = 2;
    options.warmup = 1;
    options.keep_maps = true;
    auto m = render::measure_scene(*r, rs.scene, rs.views(), analysis, options);
    ASSERT_EQ(m.modes.size(), 3u);
    EXPECT_EQ(m.modes[0].mode, render::Mode::overpaint);
    EXPECT_EQ(m.modes[0].counts.draw_calls, std::int64_t(rs.scene.elements.size()));
    EXPECT_EQ(m.modes[0].counts.triangles, 2 * std::int64_t(rs.scene.elements.size()));
    for (const auto& mode : m.modes) {
        SCOPED_TRACE(render::mode_name(mode.mode));
        // Every triangle lies inside the viewport or crosses it away from pixel centres.
        EXPECT_DOUBLE_EQ(mode.overdraw, mode.cpu_overdraw);
        EXPECT_EQ(mode.causes.elsewhere, 0);
        EXPECT_LE(m.ideal_overdraw, mode.overdraw);
        EXPECT_GT(mode.ms_median, 0.0);
        EXPECT_EQ(mode.map.counts.size(), std::size_t(64 * 48));
    }
    EXPECT_LE(m.modes[2].overdraw, m.modes[0].overdraw);
}

} // namespace
} // namespace depthcull

namespace depthcull {
namespace {

TEST(GlRender, EglPlatformsDrawTheSameFrame) {
    REQUIRE_GL(shared);
    auto rs = test::mixed_scene();
    std::vector<Image> frames;
    for (auto platform : {render::GlPlatform::surfaceless, render::GlPlatform::device}) {
        std::unique_ptr<render::GlRenderer> r;
        try {
            r = render::GlRenderer::create({platform});
        } catch (const render::NoContext& e) {
            std::printf("skipping one platform: %s\n", e.what());
            continue;
        }
        r->set_images(rs.views(), Filter::nearest);
        frames.push_back(draw(*r, overpaint_meshes(rs.scene, 0, true), nullptr, element_maps(rs.scene)));
    }
    // The shared renderer still works after other contexts came and went.
    shared->set_images(rs.views(), Filter::nearest);
    const Image reference = draw(*shared, overpaint_meshes(rs.scene, 0, true), nullptr, element_maps(rs.scene));
    for (const Image& f : frames) EXPECT_EQ(f.rgba, reference.rgba);
}

} // namespace
} // namespace depthcull

namespace depthcull {
namespace {

// glvnd's libEGL reads __EGL_VENDOR_LIBRARY_FILENAMES once, at the first EGL
// call; a path with no vendor file leaves EGL without a driver, so no
// platform has a context on any machine. The "threadsafe" death test runs
// the statement in this program started afresh (with the variable set), as
// other tests here have loaded the driver already. The child prints the
// message in brackets and exits 0 when it is NoContext's one line.
constexpr const char* kNoVendor = "/nonexistent/depthcull_no_egl_vendor.json";

[[noreturn]] void exit_with(const render::NoContext& e) {
    std::fprintf(stderr, "[%s]\n", e.what());
    std::_Exit(std::strchr(e.what(), '\n') ? 3 : 0);
}

TEST(GlRenderDeathTest, NoContextIsThrownNotNull) {
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    const char* before = std::getenv("__EGL_VENDOR_LIBRARY_FILENAMES");
    const std::string saved = before ? before : "";
    ::setenv("__EGL_VENDOR_LIBRARY_FILENAMES", kNoVendor, 1);
    EXPECT_EXIT(
        {
            try {
                auto host = render::GlHost::create({render::GlPlatform::device}, render::GlApi::desktop);
                std::fprintf(stderr, "a host: %s\n", host ? host->description().c_str() : "null");
            } catch (const render::NoContext& e) {
                exit_with(e);
            }
            std::_Exit(2);
        },
        ::testing::ExitedWithCode(0), "\\[no OpenGL context: EGL device: [^]]*\\]");
    EXPECT_EXIT(
        {
            try {
                auto renderer = render::GlRenderer::create({});
                std::fprintf(stderr, "a renderer: %s\n", renderer ? renderer->description().c_str() : "null");
            } catch (const render::NoContext& e) {
                exit_with(e);
            }
            std::_Exit(2);
        },
        ::testing::ExitedWithCode(0), "\\[no OpenGL context: [^]]*\\]");
    if (before) ::setenv("__EGL_VENDOR_LIBRARY_FILENAMES", saved.c_str(), 1);
    else ::unsetenv("__EGL_VENDOR_LIBRARY_FILENAMES");
}

} // namespace
} // namespace depthcull
