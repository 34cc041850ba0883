// The C API's renderer (dc_renderer_*) in a headless host context: it draws
// what depthcull::runtime draws for the same meshes and dynamic elements,
// pixel for pixel, and bad input is a status with a message.
#ifdef DEPTHCULL_TEST_CAPI_RUNTIME

#include <cmath>
#include <cstring>

#include <gtest/gtest.h>

#include "depthcull/depthcull.h"
#include "depthcull/frame.h"
#include "depthcull/render.h"
#include "depthcull/runtime.h"
#include "depthcull/scene.h"
#include "testing/ascii_image.h"

namespace depthcull::test {
namespace {

Image sprite() {
    return ascii_image({"..........", "...++++...", "..+####+..", ".+######+.", ".+######+.", ".+######+.", ".+######+.", "..+####+..",
                        "...++++...", ".........."});
}

struct Host {
    std::unique_ptr<render::GlHost> host;
    std::string why; // render::NoContext's, when there is no host
    Host() {
        try {
            host = render::GlHost::create({}, render::GlApi::desktop);
        } catch (const render::NoContext& e) {
            why = e.what();
        }
    }
};

// The host's loader as C sees it.
dc_gl_function gl_function(const char* name) { return reinterpret_cast<dc_gl_function>(render::GlHost::get_proc_address(name)); }

#define NEED_HOST(h)                                                                   \
    Host h;                                                                            \
    if (!h.host) GTEST_SKIP() << h.why

TEST(CApiRuntime, DrawsWhatTheCppRuntimeDraws) {
    NEED_HOST(h);
    const Image image = sprite();
    const dc_rect whole{0, 0, 10, 10};
    dc_analysis* a = nullptr;
    ASSERT_EQ(dc_analyze_image(image.rgba.data(), 10, 10, 40, whole, nullptr, &a), DC_OK);
    dc_scene* scene = nullptr;
    ASSERT_EQ(dc_scene_create({0, 0, 48, 40}, &scene), DC_OK);
    ASSERT_EQ(dc_scene_add_image(scene, "s", "s.png", 10, 10, nullptr), DC_OK);
    std::vector<dc_element> elements(24);
    for (std::size_t i = 0; i < elements.size(); ++i) {
        dc_element_default(&elements[i]);
        elements[i].rect = whole;
        elements[i].transform[4] = double((i * 7) % 38);
        elements[i].transform[5] = double((i * 5) % 30);
        elements[i].color[1] = float(i % 3) / 2;
        elements[i].blend = i % 6 == 5 ? DC_BLEND_ADD : DC_BLEND_ALPHA;
        ASSERT_EQ(dc_scene_add_element(scene, &elements[i], a), DC_OK);
    }
    dc_reconstruct_options options;
    dc_reconstruct_options_default(&options);
    options.reserved_dynamic_levels = 2;
    dc_meshes *meshes = nullptr, *frame = nullptr;
    ASSERT_EQ(dc_reconstruct(scene, &options, &meshes), DC_OK);
    ASSERT_EQ(dc_meshes_create(&frame), DC_OK);
    dc_element moving[2] = {elements[0], elements[1]};
    moving[0].transform[4] = 20, moving[1].transform[4] = 24;
    const dc_analysis* analyses[2] = {a, a};
    ASSERT_EQ(dc_add_dynamic_elements(meshes, scene, moving, analyses, 2, frame), DC_OK);

    // Through C.
    dc_renderer* r = nullptr;
    ASSERT_EQ(dc_renderer_create(&gl_function, &r), DC_OK) << dc_last_error();
    EXPECT_NE(std::string(dc_renderer_gl_version(r)), "");
    const dc_image_pixels pixels{image.rgba.data(), 10, 10, 40};
    ASSERT_EQ(dc_renderer_upload_images(r, &pixels, 1, DC_FILTER_NEAREST), DC_OK) << dc_last_error();
    ASSERT_EQ(dc_renderer_set_meshes(r, meshes), DC_OK) << dc_last_error();
    ASSERT_EQ(dc_renderer_reserve_dynamic(r, 1024, 4096), DC_OK);
    h.host->bind_framebuffer(48, 40);
    const dc_camera camera{0, 0, 48, 40, 0};
    const dc_frame_options frame_options{1, 1};
    dc_frame_counts counts;
    ASSERT_EQ(dc_renderer_draw(r, &camera, frame, &frame_options, &counts), DC_OK) << dc_last_error();
    const Image from_c = h.host->read_pixels();
    EXPECT_EQ(std::size_t(counts.draw_calls), dc_meshes_draw_count(meshes) + dc_meshes_draw_count(frame));
    EXPECT_GT(counts.samples_passed, 0);

    // Through C++, from the draws the C API handed out.
    auto draws_of = [](const dc_meshes* m) {
        std::vector<Draw> out(dc_meshes_draw_count(m));
        for (std::size_t i = 0; i < out.size(); ++i) {
            dc_draw d;
            EXPECT_EQ(dc_meshes_draw(m, i, &d), DC_OK);
            out[i].image = int(d.image);
            out[i].pass = d.pass == DC_PASS_OPAQUE ? Pass::opaque : Pass::blend;
            out[i].blend = Blend(d.blend);
            out[i].vertices.assign(d.vertices, d.vertices + d.vertex_count * DC_VERTEX_FLOATS);
            out[i].indices.assign(d.indices, d.indices + d.index_count);
        }
        return out;
    };
    std::string error;
    auto cpp = runtime::Renderer::create(&render::GlHost::get_proc_address, &error);
    ASSERT_TRUE(cpp) << error;
    const ImageView view = image.view();
    ASSERT_EQ(cpp->upload_images({&view, 1}, Filter::nearest), runtime::Status::ok);
    SceneMeshes static_meshes;
    dc_meshes_info info;
    ASSERT_EQ(dc_meshes_info_get(meshes, &info), DC_OK);
    static_meshes.viewport = {0, 0, 48, 40};
    static_meshes.depth_test = info.depth_test != 0;
    static_meshes.draws = draws_of(meshes);
    ASSERT_EQ(cpp->set_meshes(static_meshes), runtime::Status::ok);
    runtime::FrameOptions o;
    o.clear_color = true;
    ASSERT_EQ(cpp->draw({0, 0, 48, 40, false}, draws_of(frame), o), runtime::Status::ok);
    const Image from_cpp = h.host->read_pixels();
    EXPECT_EQ(from_c.rgba, from_cpp.rgba);
    std::int64_t drawn = 0;
    for (std::size_t i = 3; i < from_c.rgba.size(); i += 4) drawn += from_c.rgba[i] != 0;
    EXPECT_GT(drawn, 48 * 40 / 4);

    // A draw naming an image with no texture: a status and the runtime's message.
    const char* two_images = R"({"viewport": {"x": 0, "y": 0, "width": 8, "height": 8}, "depth_test": false,
        "images": [{"id": "a", "path": "a.png", "width": 4, "height": 4}, {"id": "b", "path": "b.png", "width": 4, "height": 4}],
        "draws": [{"image": "b", "pass": "blend", "blend": "alpha",
          "vertices": [0,0,0.5,0,0,1,1,1,1, 4,0,0.5,1,0,1,1,1,1, 0,4,0.5,0,1,1,1,1,1], "indices": [0,1,2]}]})";
    dc_meshes* bad = nullptr;
    ASSERT_EQ(dc_meshes_read_memory(two_images, std::strlen(two_images), nullptr, &bad), DC_OK) << dc_last_error();
    EXPECT_EQ(dc_renderer_set_meshes(r, bad), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(dc_last_error()).find("dc_renderer_set_meshes: "), std::string::npos) << dc_last_error();
    EXPECT_EQ(dc_renderer_draw(r, nullptr, nullptr, nullptr, nullptr), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(dc_renderer_create(nullptr, &r), DC_ERROR_INVALID_ARGUMENT);

    dc_meshes_destroy(bad);
    dc_renderer_destroy(r);
    dc_meshes_destroy(frame);
    dc_meshes_destroy(meshes);
    dc_scene_destroy(scene);
    dc_analysis_destroy(a);
}

// Sprites between a static scene's layers through C: dc_scene_add_insertion_point,
// dc_reconstruct, dc_assemble_at and dc_renderer_draw_frame draw, frame
// after frame, what overpaint of the static and moving elements in layer
// order draws (pixel centres exactly on texel edges aside).
TEST(CApiRuntime, InsertionPointFramesEqualOverpaint) {
    NEED_HOST(h);
    const Image image = sprite();
    const dc_rect whole{0, 0, 10, 10};
    dc_analysis* a = nullptr;
    ASSERT_EQ(dc_analyze_image(image.rgba.data(), 10, 10, 40, whole, nullptr, &a), DC_OK);
    const Viewport view{0, 0, 48, 40};
    dc_scene* scene = nullptr;
    ASSERT_EQ(dc_scene_create({view.x, view.y, view.width, view.height}, &scene), DC_OK);
    ASSERT_EQ(dc_scene_add_image(scene, "s", "s.png", 10, 10, nullptr), DC_OK);
    // Static layers: a background of big blobs, the game layer (12 levels),
    // then a foreground row half covering it.
    std::vector<Element> background, foreground;
    for (int i = 0; i < 6; ++i) {
        Element e;
        e.rect = {0, 0, 10, 10};
        e.transform = {2.5, 0, 0, 2.5, double(i % 3) * 16 - 6, double(i / 3) * 20 - 4};
        background.push_back(e);
    }
    for (int i = 0; i < 5; ++i) {
        Element e;
        e.rect = {0, 0, 10, 10};
        e.transform = {1, 0, 0, 1, double(i) * 10, 16};
        e.color = {0.4f, 0.8f, 1, i % 2 ? 1.0f : 0.6f};
        foreground.push_back(e);
    }
    auto add = [&](const Element& e) {
        dc_element c;
        dc_element_default(&c);
        c.rect = whole;
        std::copy(e.transform.begin(), e.transform.end(), c.transform);
        std::copy(e.color.begin(), e.color.end(), c.color);
        ASSERT_EQ(dc_scene_add_element(scene, &c, a), DC_OK);
    };
    for (const Element& e : background) add(e);
    ASSERT_EQ(dc_scene_add_insertion_point(scene, 12), DC_OK);
    for (const Element& e : foreground) add(e);
    dc_meshes* meshes = nullptr;
    ASSERT_EQ(dc_reconstruct(scene, nullptr, &meshes), DC_OK) << dc_last_error();

    dc_assembler* assembler = nullptr;
    dc_frame* frame = nullptr;
    ASSERT_EQ(dc_assembler_create(&assembler), DC_OK);
    ASSERT_EQ(dc_frame_create(&frame), DC_OK);
    uint32_t id = 0;
    ASSERT_EQ(dc_assembler_add_image(assembler, 0, 10, 10, whole, a, &id), DC_OK);
    ASSERT_EQ(dc_assembler_reserve(assembler, 12, frame), DC_OK);
    dc_renderer* r = nullptr;
    ASSERT_EQ(dc_renderer_create(&gl_function, &r), DC_OK) << dc_last_error();
    const dc_image_pixels pixels{image.rgba.data(), 10, 10, 40};
    ASSERT_EQ(dc_renderer_upload_images(r, &pixels, 1, DC_FILTER_NEAREST), DC_OK);
    ASSERT_EQ(dc_renderer_set_meshes(r, meshes), DC_OK) << dc_last_error();
    std::string error;
    auto cpp = runtime::Renderer::create(&render::GlHost::get_proc_address, &error);
    ASSERT_TRUE(cpp) << error;
    const ImageView image_view = image.view();
    ASSERT_EQ(cpp->upload_images({&image_view, 1}, Filter::nearest), runtime::Status::ok);
    std::vector<dc_sprite> sprites(12);
    for (int f = 0; f < 6; ++f) {
        Scene whole_scene;
        whole_scene.viewport = view;
        whole_scene.images = {SceneImage{"s", "s.png", 10, 10}};
        whole_scene.elements = background;
        for (std::size_t i = 0; i < sprites.size(); ++i) {
            dc_sprite_default(&sprites[i]);
            const double angle = 0.35 * double(i) + 0.2 * f, scale = 0.4 + 0.2 * double((i + f) % 6);
            const double m[6] = {scale * std::cos(angle), scale * std::sin(angle), -scale * std::sin(angle), scale * std::cos(angle),
                                 1.3 + double((i * 7 + 3 * f) % 40), 0.7 + double((i * 5 + 2 * f) % 30)};
            std::copy(m, m + 6, sprites[i].transform);
            if (i % 4 == 3) sprites[i].color[0] = 0.5f, sprites[i].color[3] = 0.7f;
            Element e;
            e.rect = {0, 0, 10, 10};
            std::copy(m, m + 6, e.transform.begin());
            std::copy(sprites[i].color, sprites[i].color + 4, e.color.begin());
            whole_scene.elements.push_back(e);
        }
        whole_scene.elements.insert(whole_scene.elements.end(), foreground.begin(), foreground.end());
        const dc_sprite* lists[1] = {sprites.data()};
        const size_t counts[1] = {sprites.size()};
        ASSERT_EQ(dc_assemble_at(assembler, meshes, lists, counts, 1, {view.x, view.y, view.width, view.height}, frame), DC_OK)
            << dc_last_error();
        h.host->bind_framebuffer(view.width, view.height);
        const dc_camera camera{view.x, view.y, view.width, view.height, 0};
        const dc_frame_options frame_options{1, 0};
        ASSERT_EQ(dc_renderer_draw_frame(r, &camera, frame, &frame_options, nullptr), DC_OK) << dc_last_error();
        const Image drawn = h.host->read_pixels();
        runtime::FrameOptions o;
        o.clear_color = true;
        ASSERT_EQ(cpp->set_meshes(overpaint_meshes(whole_scene)), runtime::Status::ok) << cpp->error();
        ASSERT_EQ(cpp->draw({view.x, view.y, view.width, view.height, false}, {}, o), runtime::Status::ok) << cpp->error();
        const Image reference = h.host->read_pixels();
        const render::ImageDiff diff = render::compare_images(reference.view(), drawn.view());
        EXPECT_EQ(diff.pixels_differ ? render::count_off_texel_edges(reference.view(), drawn.view(), whole_scene) : 0, 0)
            << "frame " << f << ": " << diff.pixels_differ << " pixels differ";
    }
    cpp.reset();
    dc_renderer_destroy(r);
    dc_frame_destroy(frame);
    dc_assembler_destroy(assembler);
    dc_meshes_destroy(meshes);
    dc_scene_destroy(scene);
    dc_analysis_destroy(a);
}

// Moving sprites through C (since 0.2): dc_assemble + dc_renderer_draw_frame
// draw what the C++ assembler and runtime draw, which equal overpaint
// (tests/runtime/test_frames.cpp).
TEST(CApiRuntime, AssembledFramesDrawLikeTheCppRuntime) {
    NEED_HOST(h);
    EXPECT_GE(DC_VERSION_MINOR, 2);
    const Image image = sprite();
    const dc_rect whole{0, 0, 10, 10};
    dc_analysis* a = nullptr;
    ASSERT_EQ(dc_analyze_image(image.rgba.data(), 10, 10, 40, whole, nullptr, &a), DC_OK);
    dc_assembler* assembler = nullptr;
    dc_frame* frame = nullptr;
    ASSERT_EQ(dc_assembler_create(&assembler), DC_OK);
    ASSERT_EQ(dc_frame_create(&frame), DC_OK);
    uint32_t id = 0;
    ASSERT_EQ(dc_assembler_add_image(assembler, 0, 10, 10, whole, a, &id), DC_OK) << dc_last_error();
    EXPECT_EQ(dc_assembler_add_image(assembler, 0, 4, 4, whole, a, &id), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(dc_last_error()).find("dc_assembler_add_image"), std::string::npos);
    std::vector<dc_sprite> sprites(30);
    std::vector<Element> elements;
    for (std::size_t i = 0; i < sprites.size(); ++i) {
        dc_sprite_default(&sprites[i]);
        sprites[i].image = 0;
        const double angle = 0.3 * double(i), scale = 0.5 + double(i % 4) / 2;
        const double m[6] = {scale * std::cos(angle), scale * std::sin(angle), -scale * std::sin(angle), scale * std::cos(angle),
                             1.3 + double((i * 7) % 40), 0.7 + double((i * 5) % 30)};
        std::copy(m, m + 6, sprites[i].transform);
        sprites[i].blend = i % 7 == 6 ? DC_BLEND_ADD : DC_BLEND_ALPHA;
    }
    ASSERT_EQ(dc_assemble(assembler, sprites.data(), sprites.size(), {0, 0, 48, 40}, frame), DC_OK) << dc_last_error();
    dc_frame_stats stats;
    ASSERT_EQ(dc_frame_stats_get(frame, &stats), DC_OK);
    EXPECT_EQ(stats.sprites, 30);
    EXPECT_LT(stats.draw_calls, 30);
    size_t vertex_count = 0, index_count = 0;
    EXPECT_NE(dc_frame_vertices(frame, &vertex_count), nullptr);
    EXPECT_NE(dc_frame_indices(frame, &index_count), nullptr);
    EXPECT_EQ(std::int64_t(index_count), 3 * stats.triangles);
    sprites[3].image = 9;
    EXPECT_EQ(dc_assemble(assembler, sprites.data(), sprites.size(), {0, 0, 48, 40}, frame), DC_ERROR_INVALID_ARGUMENT);
    sprites[3].image = 0;
    ASSERT_EQ(dc_assemble(assembler, sprites.data(), sprites.size(), {0, 0, 48, 40}, frame), DC_OK);

    dc_renderer* r = nullptr;
    ASSERT_EQ(dc_renderer_create(&gl_function, &r), DC_OK) << dc_last_error();
    const dc_image_pixels pixels{image.rgba.data(), 10, 10, 40};
    ASSERT_EQ(dc_renderer_upload_images(r, &pixels, 1, DC_FILTER_NEAREST), DC_OK);
    h.host->bind_framebuffer(48, 40);
    const dc_camera camera{0, 0, 48, 40, 0};
    const dc_frame_options frame_options{1, 0};
    dc_frame_counts counts;
    ASSERT_EQ(dc_renderer_draw_frame(r, &camera, frame, &frame_options, &counts), DC_OK) << dc_last_error();
    EXPECT_EQ(counts.draw_calls, stats.draw_calls);
    const Image from_c = h.host->read_pixels();

    // The C++ assembler and runtime, same sprites.
    std::string error;
    auto cpp = runtime::Renderer::create(&render::GlHost::get_proc_address, &error);
    ASSERT_TRUE(cpp) << error;
    const ImageView view = image.view();
    ASSERT_EQ(cpp->upload_images({&view, 1}, Filter::nearest), runtime::Status::ok);
    ImageAnalysis analysis = analyze_image(view, {0, 0, 10, 10}, {});
    FrameAssembler cpp_assembler;
    int cpp_id = -1;
    ASSERT_EQ(cpp_assembler.add_image({0, 10, 10, {0, 0, 10, 10}, &analysis}, &cpp_id), FrameStatus::ok);
    std::vector<Sprite> cpp_sprites;
    for (const dc_sprite& c : sprites) {
        Sprite s;
        std::copy(c.transform, c.transform + 6, s.transform.begin());
        s.blend = Blend(c.blend);
        cpp_sprites.push_back(s);
    }
    AssembledFrame cpp_frame;
    ASSERT_EQ(cpp_assembler.assemble(cpp_sprites, {0, 0, 48, 40}, &cpp_frame), FrameStatus::ok);
    runtime::FrameOptions o;
    o.clear_color = true;
    ASSERT_EQ(cpp->draw_frame({0, 0, 48, 40, false}, cpp_frame, o), runtime::Status::ok) << cpp->error();
    const Image from_cpp = h.host->read_pixels();
    EXPECT_EQ(from_c.rgba, from_cpp.rgba);
    std::int64_t drawn = 0;
    for (std::size_t i = 3; i < from_c.rgba.size(); i += 4) drawn += from_c.rgba[i] != 0;
    EXPECT_GT(drawn, 48 * 40 / 4);
    cpp.reset();
    dc_renderer_destroy(r);
    dc_frame_destroy(frame);
    dc_assembler_destroy(assembler);
    dc_analysis_destroy(a);
}

} // namespace
} // namespace depthcull::test

#endif
