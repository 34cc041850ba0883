// depthcull::runtime in a host's context: both targets draw, states and
// blend modes match the instrumented renderer's definition, dynamic
// elements land in front, bad input gets a status, and a frame allocates
// nothing.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include <cmath>

#include "depthcull/frame.h"
#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "../render/render_scenes.h"
#include "testing/corpus.h"
#include "runtime_host.h"

#include "testing/count_allocations.h"

namespace depthcull {
namespace {

using render::GlApi;

class Runtime : public testing::TestWithParam<GlApi> {};

TEST_P(Runtime, DrawsOverpaintOfTheMixedScene) {
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    test::RenderScene rs = test::mixed_scene();
    auto views = rs.views();
    ASSERT_EQ(h->renderer->upload_images(views, Filter::nearest), runtime::Status::ok) << h->renderer->error();
    Image frame = h->frame(overpaint_meshes(rs.scene));
    ASSERT_EQ(frame.width, rs.scene.viewport.width);
    std::int64_t drawn = 0;
    for (std::size_t i = 3; i < frame.rgba.size(); i += 4) drawn += frame.rgba[i] != 0;
    EXPECT_GT(drawn, frame.width * frame.height / 2); // the 16x background covers most of it
}

TEST_P(Runtime, BadDrawsGetAStatusAndAMessage) {
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    test::RenderScene rs = test::mixed_scene();
    auto views = rs.views();
    ASSERT_EQ(h->renderer->upload_images(views, Filter::nearest), runtime::Status::ok);
    SceneMeshes meshes = overpaint_meshes(rs.scene);
    meshes.draws[1].image = 7;
    EXPECT_EQ(h->renderer->set_meshes(meshes), runtime::Status::bad_meshes);
    EXPECT_NE(h->renderer->error().find("image 7"), std::string::npos) << h->renderer->error();
    meshes = overpaint_meshes(rs.scene);
    meshes.draws[0].indices[2] = 99;
    EXPECT_EQ(h->renderer->set_meshes(meshes), runtime::Status::bad_meshes);
    EXPECT_NE(h->renderer->error().find("index 99"), std::string::npos) << h->renderer->error();
    const ImageView empty{};
    EXPECT_EQ(h->renderer->upload_images({&empty, 1}, Filter::nearest), runtime::Status::bad_image);
}

TEST_P(Runtime, AFrameWithDynamicElementsAllocatesNothing) {
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    pipeline::PreparedScene p = pipeline::prepare_scene(test::source_path("examples/meadow.json"), {});
    const std::vector<ImageView> views = p.views();
    ASSERT_EQ(h->renderer->upload_images(views, p.scene.filter), runtime::Status::ok);
    ReconstructOptions options;
    options.reserved_dynamic_levels = 16;
    SceneMeshes static_meshes;
    ASSERT_EQ(reconstruct_scene(p.scene, p.analysis, options, &static_meshes), ReconstructStatus::ok);
    ASSERT_EQ(h->renderer->set_meshes(static_meshes), runtime::Status::ok);
    // add_dynamic_elements gives only the dynamic draws.
    std::vector<Element> moving(p.scene.elements.end() - 8, p.scene.elements.end());
    const std::vector<const ImageAnalysis*> all = p.analysis.per_element();
    std::vector<const ImageAnalysis*> analyses(all.end() - 8, all.end());
    SceneMeshes dynamic;
    ASSERT_EQ(add_dynamic_elements(static_meshes, p.scene, moving, analyses, &dynamic), ReconstructStatus::ok);
    ASSERT_FALSE(dynamic.draws.empty());
    std::size_t vertices = 0, indices = 0;
    for (const Draw& d : dynamic.draws) vertices += d.vertex_count(), indices += d.indices.size();
    ASSERT_EQ(h->renderer->reserve_dynamic(vertices, indices), runtime::Status::ok);
    h->host->bind_framebuffer(p.scene.viewport.width, p.scene.viewport.height);
    const runtime::Camera camera = runtime::camera_of(p.scene.viewport, false);
    ASSERT_EQ(h->renderer->draw(camera, dynamic.draws), runtime::Status::ok);
    const std::int64_t before = g_allocations.load();
    runtime::FrameCounts counts;
    for (int frame = 0; frame < 5; ++frame) {
        ASSERT_EQ(h->renderer->draw(camera, dynamic.draws, {}, &counts), runtime::Status::ok);
    }
    EXPECT_EQ(g_allocations.load() - before, 0);
    EXPECT_EQ(counts.draw_calls, std::int64_t(static_meshes.draws.size() + dynamic.draws.size()));
}

// Moving sprites (depthcull/frame.h): once warmed up, assembling a frame
// and drawing it allocate nothing, however the sprites move.
TEST_P(Runtime, AssembledFramesAllocateNothing) {
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    pipeline::PreparedScene p = pipeline::prepare_scene(test::source_path("examples/meadow.json"), {});
    const std::vector<ImageView> views = p.views();
    ASSERT_EQ(h->renderer->upload_images(views, p.scene.filter), runtime::Status::ok);
    FrameAssembler assembler;
    std::vector<int> picture_of; // per analysis
    for (const ImageAnalysis& a : p.analysis.images) {
        std::size_t element = 0;
        while (p.analysis.of_element[element] != std::uint32_t(&a - p.analysis.images.data())) ++element;
        const Element& e = p.scene.elements[element];
        const SceneImage& img = p.scene.images[std::size_t(e.image)];
        int id = -1;
        ASSERT_EQ(assembler.add_image({e.image, img.width, img.height, e.rect, &a}, &id), FrameStatus::ok);
        picture_of.push_back(id);
    }
    std::vector<Sprite> sprites;
    for (int i = 0; i < 2000; ++i) {
        const std::size_t element = std::size_t(i) % p.scene.elements.size();
        Sprite s;
        s.image = picture_of[p.analysis.of_element[element]];
        sprites.push_back(s);
    }
    auto move = [&](int frame) {
        for (std::size_t i = 0; i < sprites.size(); ++i) {
            const double a = 0.01 * double(i) + 0.1 * frame, scale = 0.25 + double((i * 7 + std::size_t(frame)) % 8) / 4;
            sprites[i].transform = {scale * std::cos(a), scale * std::sin(a), -scale * std::sin(a), scale * std::cos(a),
                                    double((i * 37 + std::size_t(frame) * 3) % 640), double((i * 53) % 480)};
        }
    };
    const Viewport view{0, 0, 640, 480};
    SceneMeshes none;
    none.viewport = view;
    ASSERT_EQ(h->renderer->set_meshes(none), runtime::Status::ok);
    h->host->bind_framebuffer(view.width, view.height);
    AssembledFrame frame;
    assembler.reserve(sprites.size(), &frame);
    ASSERT_EQ(h->renderer->reserve_dynamic(frame.vertices.capacity() / kVertexFloats, frame.indices.capacity()), runtime::Status::ok);
    const runtime::Camera camera = runtime::camera_of(view, false);
    move(0);
    ASSERT_EQ(assembler.assemble(sprites, view, &frame), FrameStatus::ok);
    ASSERT_EQ(h->renderer->draw_frame(camera, frame), runtime::Status::ok) << h->renderer->error();
    const std::int64_t before = g_allocations.load();
    for (int f = 1; f <= 5; ++f) {
        move(f);
        ASSERT_EQ(assembler.assemble(sprites, view, &frame), FrameStatus::ok);
        ASSERT_EQ(h->renderer->draw_frame(camera, frame), runtime::Status::ok);
    }
    EXPECT_EQ(g_allocations.load() - before, 0);
    EXPECT_GT(frame.stats.opaque_draws, 0);
    EXPECT_LT(frame.stats.blend_batches, std::int64_t(sprites.size()) / 4);
}

INSTANTIATE_TEST_SUITE_P(Targets, Runtime, testing::Values(GlApi::desktop, GlApi::gles),
                         [](const auto& info) { return info.param == GlApi::gles ? "es30" : "gl33"; });

} // namespace
} // namespace depthcull
