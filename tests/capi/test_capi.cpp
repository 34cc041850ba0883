// The C API (include/depthcull/depthcull.h) against the C++ API it wraps:
// same polygons, same draws, same files; every misuse a status and a
// message, never an exception or a crash.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <gtest/gtest.h>
#include <unistd.h>

#include "depthcull/depthcull.h"
#include "depthcull/frame.h"
#include "depthcull/io.h"
#include "depthcull/scene.h"
#include "testing/ascii_image.h"

namespace depthcull::test {
namespace {

// A blob with a transparent rim, a soft edge and an opaque core.
Image blob() {
    return ascii_image({"..........", "...++++...", "..+####+..", ".+######+.", ".+######+.", ".+######+.", ".+######+.", "..+####+..",
                        "...++++...", ".........."});
}

dc_analysis* analyze(const Image& image, dc_rect rect) {
    dc_analysis* a = nullptr;
    EXPECT_EQ(dc_analyze_image(image.rgba.data(), image.width, image.height, image.width * 4, rect, nullptr, &a), DC_OK) << dc_last_error();
    return a;
}

TEST(CApi, AnalysisIsTheCppAnalysis) {
    const Image image = blob();
    dc_analysis* a = analyze(image, {1, 1, 8, 8});
    ASSERT_NE(a, nullptr);
    const ImageAnalysis expected = analyze_image(image.view(), {1, 1, 8, 8}, {});
    ASSERT_EQ(dc_analysis_boundary_count(a), expected.boundary.size());
    ASSERT_EQ(dc_analysis_opaque_count(a), expected.opaque.size());
    for (std::size_t i = 0; i < expected.boundary.size(); ++i) {
        std::size_t n = 0;
        const dc_point* p = dc_analysis_boundary(a, i, &n);
        ASSERT_EQ(n, expected.boundary[i].size());
        for (std::size_t k = 0; k < n; ++k) EXPECT_EQ((Vec2{p[k].x, p[k].y}), expected.boundary[i][k]);
    }
    std::size_t n = 7;
    EXPECT_EQ(dc_analysis_opaque(a, 99, &n), nullptr);
    EXPECT_EQ(n, 0u);
    dc_image_stats stats;
    ASSERT_EQ(dc_analysis_stats(a, &stats), DC_OK);
    EXPECT_EQ(stats.nontransparent_texels, expected.stats.nontransparent_texels);
    EXPECT_EQ(stats.opaque_covered_texels, expected.stats.opaque_covered_texels);
    EXPECT_EQ(dc_analysis_rect(a).w, 8);
    dc_analysis_destroy(a);
    dc_analysis_destroy(nullptr);
}

TEST(CApi, MisuseIsAStatusWithAMessage) {
    const Image image = blob();
    dc_analysis* a = nullptr;
    EXPECT_EQ(dc_analyze_image(nullptr, 10, 10, 40, {0, 0, 10, 10}, nullptr, &a), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(dc_analyze_image(image.rgba.data(), 10, 10, 40, {5, 5, 10, 10}, nullptr, &a), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_analyze_image: rect is empty or outside the 10x10 image");
    EXPECT_EQ(dc_analyze_image(image.rgba.data(), 10, 10, 8, {0, 0, 10, 10}, nullptr, &a), DC_ERROR_INVALID_ARGUMENT);
    dc_analyze_options o;
    dc_analyze_options_default(&o);
    o.min_opaque_coverage = 2;
    EXPECT_EQ(dc_analyze_image(image.rgba.data(), 10, 10, 40, {0, 0, 10, 10}, &o, &a), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(a, nullptr); // outputs are written only on success

    dc_scene* scene = nullptr;
    EXPECT_EQ(dc_scene_create({0, 0, 0, 10}, &scene), DC_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ(dc_scene_create({0, 0, 64, 64}, &scene), DC_OK);
    EXPECT_EQ(dc_scene_add_image(scene, "b", "b.png", 10, 10, nullptr), DC_OK);
    EXPECT_EQ(dc_scene_add_image(scene, "b", "c.png", 10, 10, nullptr), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_scene_add_image: duplicate image id \"b\"");
    dc_element e;
    dc_element_default(&e);
    e.rect = {0, 0, 10, 10};
    EXPECT_EQ(dc_scene_add_element(scene, &e, nullptr), DC_ERROR_INVALID_ARGUMENT); // alpha needs its analysis
    EXPECT_STREQ(dc_last_error(), "dc_scene_add_element: element 0: an alpha or add element needs its analysis");
    e.blend = DC_BLEND_OPAQUE;
    EXPECT_EQ(dc_scene_add_element(scene, &e, nullptr), DC_OK);
    dc_analysis* other = analyze(image, {1, 1, 8, 8});
    e.blend = DC_BLEND_ALPHA;
    EXPECT_EQ(dc_scene_add_element(scene, &e, other), DC_ERROR_INVALID_ARGUMENT); // analysis of another rect
    e.transform[0] = std::nan("");
    e.rect = {1, 1, 8, 8};
    EXPECT_EQ(dc_scene_add_element(scene, &e, other), DC_ERROR_INVALID_ARGUMENT);
    e.image = 3;
    EXPECT_EQ(dc_scene_add_element(scene, &e, other), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(dc_scene_element_count(scene), 1u);
    dc_analysis_destroy(other);
    dc_scene_destroy(scene);

    dc_meshes* m = nullptr;
    EXPECT_EQ(dc_meshes_read_file("/nonexistent/m.json", &m), DC_ERROR_IO);
    EXPECT_NE(std::string(dc_last_error()).find("/nonexistent/m.json"), std::string::npos);
    EXPECT_EQ(dc_meshes_read_memory("DCMESH\0\0\1", 9, nullptr, &m), DC_ERROR_IO);
    EXPECT_STREQ(dc_last_error(), "memory: byte 8: the file ends inside the header");
    EXPECT_EQ(m, nullptr);
    EXPECT_EQ(dc_meshes_draw_count(nullptr), 0u);
    EXPECT_STREQ(dc_status_string(DC_ERROR_TOO_MANY_DEPTH_LEVELS), "too many depth levels");
}

// A scene of blobs and opaque tiles, built through the C API and through
// C++ from the same values.
struct Scenes {
    dc_scene* c = nullptr;
    dc_analysis* blob = nullptr;
    Scene cpp;
    ImageAnalysis blob_analysis;
    std::vector<const ImageAnalysis*> analyses;
};

Scenes both_scenes(const Image& image) {
    Scenes s;
    EXPECT_EQ(dc_scene_create({0, 0, 64, 48}, &s.c), DC_OK);
    EXPECT_EQ(dc_scene_add_image(s.c, "blob", "art/blob.png", 10, 10, nullptr), DC_OK);
    s.blob = analyze(image, {0, 0, 10, 10});
    s.blob_analysis = analyze_image(image.view(), {0, 0, 10, 10}, {});
    s.cpp.viewport = {0, 0, 64, 48};
    s.cpp.images = {SceneImage{"blob", "art/blob.png", 10, 10}};
    for (int i = 0; i < 30; ++i) {
        dc_element e;
        dc_element_default(&e);
        e.rect = {0, 0, 10, 10};
        e.transform[4] = (i * 7) % 50;
        e.transform[5] = (i * 5) % 36;
        e.blend = i % 7 == 3 ? DC_BLEND_OPAQUE : DC_BLEND_ALPHA;
        EXPECT_EQ(dc_scene_add_element(s.c, &e, s.blob), DC_OK) << dc_last_error();
        Element x;
        x.rect = {0, 0, 10, 10};
        x.transform = {1, 0, 0, 1, e.transform[4], e.transform[5]};
        x.blend = Blend(e.blend);
        s.cpp.elements.push_back(x);
        s.analyses.push_back(&s.blob_analysis);
    }
    return s;
}

void expect_draws_equal(const dc_meshes* c, const std::vector<Draw>& draws) {
    ASSERT_EQ(dc_meshes_draw_count(c), draws.size());
    for (std::size_t i = 0; i < draws.size(); ++i) {
        dc_draw d;
        ASSERT_EQ(dc_meshes_draw(c, i, &d), DC_OK);
        EXPECT_EQ(d.image, std::uint32_t(draws[i].image));
        EXPECT_EQ(d.pass, draws[i].pass == Pass::opaque ? DC_PASS_OPAQUE : DC_PASS_BLEND);
        EXPECT_EQ(d.blend, int(draws[i].blend));
        EXPECT_EQ(std::vector<float>(d.vertices, d.vertices + d.vertex_count * DC_VERTEX_FLOATS), draws[i].vertices);
        EXPECT_EQ(std::vector<std::uint32_t>(d.indices, d.indices + d.index_count), draws[i].indices);
    }
}

TEST(CApi, ReconstructionAndDynamicElementsAreTheCppOnes) {
    const Image image = blob();
    Scenes s = both_scenes(image);
    dc_reconstruct_options options;
    dc_reconstruct_options_default(&options);
    options.reserved_dynamic_levels = 4;
    dc_meshes* meshes = nullptr;
    options.texel_margin = 1;
    EXPECT_EQ(dc_reconstruct(s.c, &options, &meshes), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_reconstruct: texel_margin must be in 0..0.25");
    options.texel_margin = kTexelMargin;
    ASSERT_EQ(dc_reconstruct(s.c, &options, &meshes), DC_OK) << dc_last_error();
    ReconstructOptions cpp_options;
    cpp_options.reserved_dynamic_levels = 4;
    SceneMeshes expected;
    ASSERT_EQ(reconstruct_scene(s.cpp, s.analyses, cpp_options, &expected), ReconstructStatus::ok);
    expect_draws_equal(meshes, expected.draws);
    dc_meshes_info info;
    ASSERT_EQ(dc_meshes_info_get(meshes, &info), DC_OK);
    EXPECT_EQ(info.stats.elements, 30);
    EXPECT_EQ(info.stats.depth_levels, expected.stats.depth_levels);
    EXPECT_EQ(info.depth_test, 1);
    dc_image_info img;
    ASSERT_EQ(dc_meshes_image(meshes, 0, &img), DC_OK);
    EXPECT_STREQ(img.path, "art/blob.png");

    // Dynamic elements: the frame holds only their draws, the C++ frame's
    // first (opaque) and last (blend) draws around the static ones.
    dc_meshes* frame = nullptr;
    ASSERT_EQ(dc_meshes_create(&frame), DC_OK);
    dc_element moving[3];
    const dc_analysis* analyses[3] = {s.blob, s.blob, s.blob};
    std::vector<Element> cpp_moving;
    for (int i = 0; i < 3; ++i) {
        dc_element_default(&moving[i]);
        moving[i].rect = {0, 0, 10, 10};
        moving[i].transform[4] = 10 + 9 * i;
        moving[i].transform[5] = 12;
        Element x;
        x.rect = {0, 0, 10, 10};
        x.transform = {1, 0, 0, 1, moving[i].transform[4], 12};
        cpp_moving.push_back(x);
    }
    for (int f = 0; f < 2; ++f) ASSERT_EQ(dc_add_dynamic_elements(meshes, s.c, moving, analyses, 3, frame), DC_OK) << dc_last_error();
    SceneMeshes cpp_frame;
    ASSERT_EQ(add_dynamic_elements(expected, s.cpp, cpp_moving, {&s.blob_analysis, &s.blob_analysis, &s.blob_analysis}, &cpp_frame),
              ReconstructStatus::ok);
    // Both give only the dynamic draws.
    expect_draws_equal(frame, cpp_frame.draws);
    EXPECT_GT(dc_meshes_draw_count(frame), 0u);

    // More than fit above the static levels (D = 256 here): a status.
    std::vector<dc_element> many(200, moving[0]);
    std::vector<const dc_analysis*> many_analyses(200, s.blob);
    EXPECT_EQ(dc_add_dynamic_elements(meshes, s.c, many.data(), many_analyses.data(), many.size(), frame), DC_ERROR_TOO_MANY_DEPTH_LEVELS);
    EXPECT_EQ(info.stats.depth_bits, 10);

    dc_meshes_destroy(frame);
    dc_meshes_destroy(meshes);
    dc_analysis_destroy(s.blob);
    dc_scene_destroy(s.c);
}

// Insertion points through C: a scene with a point between its layers,
// reconstructed, and sprites assembled at the point give the C++ meshes,
// points and frame; misuse is a status.
TEST(CApi, InsertionPointFramesAreTheCppOnes) {
    const Image image = blob();
    dc_scene* scene = nullptr;
    ASSERT_EQ(dc_scene_create({0, 0, 64, 48}, &scene), DC_OK);
    ASSERT_EQ(dc_scene_add_image(scene, "blob", "art/blob.png", 10, 10, nullptr), DC_OK);
    dc_analysis* a = analyze(image, {0, 0, 10, 10});
    Scene cpp;
    cpp.viewport = {0, 0, 64, 48};
    cpp.images = {SceneImage{"blob", "art/blob.png", 10, 10}};
    const ImageAnalysis analysis = analyze_image(image.view(), {0, 0, 10, 10}, {});
    std::vector<const ImageAnalysis*> analyses;
    ReconstructOptions cpp_options;
    EXPECT_EQ(dc_scene_add_insertion_point(scene, -1), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(dc_scene_add_insertion_point(nullptr, 4), DC_ERROR_INVALID_ARGUMENT);
    for (int i = 0; i < 12; ++i) {
        if (i == 5) { // the game layer: sprites go between elements 4 and 5
            ASSERT_EQ(dc_scene_add_insertion_point(scene, 8), DC_OK);
            cpp_options.insertion_points.push_back({5, 8});
        }
        dc_element e;
        dc_element_default(&e);
        e.rect = {0, 0, 10, 10};
        e.transform[4] = (i * 7) % 50;
        e.transform[5] = (i * 5) % 36;
        ASSERT_EQ(dc_scene_add_element(scene, &e, a), DC_OK);
        Element x;
        x.rect = {0, 0, 10, 10};
        x.transform = {1, 0, 0, 1, e.transform[4], e.transform[5]};
        cpp.elements.push_back(x);
        analyses.push_back(&analysis);
    }
    dc_meshes* meshes = nullptr;
    ASSERT_EQ(dc_reconstruct(scene, nullptr, &meshes), DC_OK) << dc_last_error();
    SceneMeshes expected;
    ASSERT_EQ(reconstruct_scene(cpp, analyses, cpp_options, &expected), ReconstructStatus::ok);
    expect_draws_equal(meshes, expected.draws);
    ASSERT_EQ(dc_meshes_insertion_point_count(meshes), 1u);
    dc_insertion_point point;
    ASSERT_EQ(dc_meshes_insertion_point(meshes, 0, &point), DC_OK);
    EXPECT_EQ(point.element, 5u);
    EXPECT_EQ(point.levels, 8);
    EXPECT_EQ(point.first_level, expected.insertion_points[0].first_level);
    EXPECT_EQ(point.blend_draw, expected.insertion_points[0].blend_draw);
    EXPECT_EQ(dc_meshes_insertion_point(meshes, 1, &point), DC_ERROR_INVALID_ARGUMENT);

    // Sprites at the point, turned and scaled: the C++ assembler's frame.
    dc_assembler* assembler = nullptr;
    dc_frame* frame = nullptr;
    ASSERT_EQ(dc_assembler_create(&assembler), DC_OK);
    ASSERT_EQ(dc_frame_create(&frame), DC_OK);
    uint32_t id = 0;
    ASSERT_EQ(dc_assembler_add_image(assembler, 0, 10, 10, {0, 0, 10, 10}, a, &id), DC_OK);
    FrameAssembler cpp_assembler;
    int cpp_id = -1;
    ASSERT_EQ(cpp_assembler.add_image({0, 10, 10, {0, 0, 10, 10}, &analysis}, &cpp_id), FrameStatus::ok);
    std::vector<dc_sprite> sprites(8);
    std::vector<Sprite> cpp_sprites(8);
    for (std::size_t i = 0; i < sprites.size(); ++i) {
        dc_sprite_default(&sprites[i]);
        const double angle = 0.4 * double(i), scale = 0.5 + 0.25 * double(i % 5);
        const double m[6] = {scale * std::cos(angle), scale * std::sin(angle), -scale * std::sin(angle), scale * std::cos(angle),
                             3.3 + 6.1 * double(i), 20.6 - double(i)};
        std::copy(m, m + 6, sprites[i].transform);
        std::copy(m, m + 6, cpp_sprites[i].transform.begin());
        if (i % 3 == 1) sprites[i].color[3] = cpp_sprites[i].color[3] = 0.5f;
    }
    const dc_sprite* lists[1] = {sprites.data()};
    size_t counts[1] = {sprites.size()};
    for (int f = 0; f < 2; ++f) ASSERT_EQ(dc_assemble_at(assembler, meshes, lists, counts, 1, {0, 0, 64, 48}, frame), DC_OK) << dc_last_error();
    const std::span<const Sprite> cpp_lists[1] = {cpp_sprites};
    AssembledFrame cpp_frame;
    ASSERT_EQ(cpp_assembler.assemble_at(expected, cpp_lists, {0, 0, 64, 48}, &cpp_frame), FrameStatus::ok);
    size_t vertex_count = 0, index_count = 0;
    const float* vertices = dc_frame_vertices(frame, &vertex_count);
    const uint32_t* indices = dc_frame_indices(frame, &index_count);
    EXPECT_EQ(std::vector<float>(vertices, vertices + vertex_count * DC_VERTEX_FLOATS), std::vector<float>(cpp_frame.vertices.begin(), cpp_frame.vertices.end()));
    EXPECT_EQ(std::vector<uint32_t>(indices, indices + index_count), std::vector<uint32_t>(cpp_frame.indices.begin(), cpp_frame.indices.end()));
    ASSERT_EQ(dc_frame_draw_count(frame), cpp_frame.draws.size());
    for (std::size_t i = 0; i < cpp_frame.draws.size(); ++i) {
        dc_frame_draw d;
        ASSERT_EQ(dc_frame_draw_get(frame, i, &d), DC_OK);
        EXPECT_EQ(d.image, uint32_t(cpp_frame.draws[i].image));
        EXPECT_EQ(d.pass, cpp_frame.draws[i].pass == Pass::opaque ? DC_PASS_OPAQUE : DC_PASS_BLEND);
        EXPECT_EQ(d.blend, int(cpp_frame.draws[i].blend));
        EXPECT_EQ(d.first_index, cpp_frame.draws[i].first_index);
        EXPECT_EQ(d.index_count, cpp_frame.draws[i].index_count);
    }
    ASSERT_EQ(dc_frame_point_count(frame), 1u);
    dc_frame_point fp;
    ASSERT_EQ(dc_frame_point_get(frame, 0, &fp), DC_OK);
    EXPECT_EQ(fp.static_draw, point.blend_draw);
    EXPECT_EQ(fp.first_draw, cpp_frame.points[0].first_draw);
    EXPECT_EQ(fp.end_draw, cpp_frame.points[0].end_draw);
    EXPECT_GT(fp.end_draw, fp.first_draw);
    EXPECT_EQ(dc_frame_draw_get(frame, 999, nullptr), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(dc_frame_point_get(frame, 1, &fp), DC_ERROR_INVALID_ARGUMENT);

    // Misuse: more sprites than the point's levels, more lists than points,
    // a missing list, meshes without points.
    std::vector<dc_sprite> many(9, sprites[0]);
    const dc_sprite* many_lists[1] = {many.data()};
    size_t many_counts[1] = {many.size()};
    EXPECT_EQ(dc_assemble_at(assembler, meshes, many_lists, many_counts, 1, {0, 0, 64, 48}, frame), DC_ERROR_TOO_MANY_DEPTH_LEVELS);
    const dc_sprite* two_lists[2] = {sprites.data(), sprites.data()};
    size_t two_counts[2] = {1, 1};
    EXPECT_EQ(dc_assemble_at(assembler, meshes, two_lists, two_counts, 2, {0, 0, 64, 48}, frame), DC_ERROR_INVALID_ARGUMENT);
    const dc_sprite* null_list[1] = {nullptr};
    EXPECT_EQ(dc_assemble_at(assembler, meshes, null_list, counts, 1, {0, 0, 64, 48}, frame), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(dc_last_error()).find("dc_assemble_at"), std::string::npos);
    dc_meshes* plain = nullptr;
    ASSERT_EQ(dc_meshes_create(&plain), DC_OK);
    EXPECT_EQ(dc_meshes_insertion_point_count(plain), 0u);
    EXPECT_EQ(dc_assemble_at(assembler, plain, lists, counts, 1, {0, 0, 64, 48}, frame), DC_ERROR_INVALID_ARGUMENT);
    // No lists: a frame of no sprites, the static meshes alone.
    ASSERT_EQ(dc_assemble_at(assembler, meshes, nullptr, nullptr, 0, {0, 0, 64, 48}, frame), DC_OK) << dc_last_error();
    EXPECT_EQ(dc_frame_draw_count(frame), 0u);

    dc_meshes_destroy(plain);
    dc_frame_destroy(frame);
    dc_assembler_destroy(assembler);
    dc_meshes_destroy(meshes);
    dc_analysis_destroy(a);
    dc_scene_destroy(scene);
}

TEST(CApi, MeshFilesAreTheIoOnes) {
    const Image image = blob();
    Scenes s = both_scenes(image);
    dc_meshes* meshes = nullptr;
    ASSERT_EQ(dc_reconstruct(s.c, nullptr, &meshes), DC_OK);
    // The scene's analysis handle may go before the scene.
    dc_analysis_destroy(s.blob);
    SceneMeshes expected;
    ASSERT_EQ(reconstruct_scene(s.cpp, s.analyses, {}, &expected), ReconstructStatus::ok);

    const auto dir = std::filesystem::temp_directory_path() / ("dc_capi_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string json = (dir / "m.json").string(), bin = (dir / "m.bin").string();
    ASSERT_EQ(dc_meshes_write_file(meshes, json.c_str(), DC_FORMAT_JSON, DC_WRITE_NO_TIMING), DC_OK) << dc_last_error();
    ASSERT_EQ(dc_meshes_write_file(meshes, bin.c_str(), DC_FORMAT_BINARY, DC_WRITE_NO_TIMING), DC_OK);
    EXPECT_EQ(io::read_file(json), io::meshes_to_json(io::meshes_document(s.cpp, expected), json));
    EXPECT_EQ(io::read_file(bin), io::meshes_to_binary(io::meshes_document(s.cpp, expected), bin));

    dc_meshes *from_json = nullptr, *from_memory = nullptr;
    ASSERT_EQ(dc_meshes_read_file(json.c_str(), &from_json), DC_OK);
    expect_draws_equal(from_json, expected.draws);
    void* data = nullptr;
    std::size_t size = 0;
    ASSERT_EQ(dc_meshes_write_memory(from_json, DC_FORMAT_BINARY, DC_WRITE_NO_TIMING, &data, &size), DC_OK);
    ASSERT_EQ(dc_meshes_read_memory(data, size, nullptr, &from_memory), DC_OK);
    expect_draws_equal(from_memory, expected.draws);
    dc_free(data);
    std::filesystem::remove_all(dir);
    dc_meshes_destroy(from_memory);
    dc_meshes_destroy(from_json);
    dc_meshes_destroy(meshes);
    dc_scene_destroy(s.c);
}

// stats.seconds is measured at the edge: dc_reconstruct times itself (the
// library's SceneStats hold no clock reading) and dc_meshes_info_get
// reports it, but the files the C API writes say 0 with or without
// DC_WRITE_NO_TIMING (the same meshes are the same bytes), and a file read
// back reports its own stats.seconds without writing it again. No bound on
// the time itself: a loaded machine may take any time (tests assert no
// timings).
TEST(CApi, ReconstructionSecondsAreTimedAtTheEdge) {
    const Image image = blob();
    Scenes s = both_scenes(image);
    dc_meshes* meshes = nullptr;
    ASSERT_EQ(dc_reconstruct(s.c, nullptr, &meshes), DC_OK);
    dc_meshes_info info{};
    ASSERT_EQ(dc_meshes_info_get(meshes, &info), DC_OK);
    EXPECT_TRUE(std::isfinite(info.stats.seconds));
    for (const unsigned flags : {0u, unsigned(DC_WRITE_NO_TIMING)}) {
        void* data = nullptr;
        std::size_t size = 0;
        ASSERT_EQ(dc_meshes_write_memory(meshes, DC_FORMAT_BINARY, flags, &data, &size), DC_OK);
        dc_meshes* back = nullptr;
        ASSERT_EQ(dc_meshes_read_memory(data, size, nullptr, &back), DC_OK);
        dc_meshes_info back_info{};
        ASSERT_EQ(dc_meshes_info_get(back, &back_info), DC_OK);
        EXPECT_EQ(back_info.stats.seconds, 0.0);
        dc_meshes_destroy(back);
        dc_free(data);
    }
    // A file that says 2.5 (`depthcull optimize` writes its time there:
    // binary bytes 96..103) reports it, and the C API writes it back as 0.
    void* data = nullptr;
    std::size_t size = 0;
    ASSERT_EQ(dc_meshes_write_memory(meshes, DC_FORMAT_BINARY, 0, &data, &size), DC_OK);
    const std::string untimed(static_cast<const char*>(data), size);
    dc_free(data);
    std::string timed = untimed;
    const double seconds = 2.5;
    std::memcpy(timed.data() + 96, &seconds, 8);
    dc_meshes* back = nullptr;
    ASSERT_EQ(dc_meshes_read_memory(timed.data(), timed.size(), nullptr, &back), DC_OK);
    ASSERT_EQ(dc_meshes_info_get(back, &info), DC_OK);
    EXPECT_EQ(info.stats.seconds, 2.5);
    ASSERT_EQ(dc_meshes_write_memory(back, DC_FORMAT_BINARY, 0, &data, &size), DC_OK);
    EXPECT_EQ(std::string(static_cast<const char*>(data), size), untimed);
    dc_free(data);
    dc_meshes_destroy(back);
    dc_meshes_destroy(meshes);
    dc_analysis_destroy(s.blob);
    dc_scene_destroy(s.c);
}

// Animations read from either form are the C API's, and written back
// (either form) they stay.
TEST(CApi, MeshAnimationsAreTheFileOnes) {
    const std::string text = R"({"viewport": {"x": 0, "y": 0, "width": 8, "height": 8}, "depth_test": true,
 "images": [{"id": "a", "path": "a.png", "width": 4, "height": 4}],
 "draws": [{"image": "a", "pass": "blend", "blend": "alpha",
   "vertices": [0,0,0.5,0,0,1,1,1,1, 4,0,0.5,1,0,1,1,1,1, 0,4,0.5,0,1,1,1,1,1], "indices": [0,1,2]}],
 "stats": {"elements": 1, "draw_calls": 1, "triangles": 1, "depth_levels": 64, "depth_bits": 10, "graph_edges": 0, "seconds": 0},
 "animations": [{"frames": [{"image": 0, "rect": [0, 0, 2, 2], "duration": 100}, {"image": 0, "rect": [2, 0, 2, 2], "duration": 50}]}],
 "animated": [{"draw": 0, "first_vertex": 1, "vertex_count": 2, "animation": 0}]})";
    dc_meshes* from_json = nullptr;
    ASSERT_EQ(dc_meshes_read_memory(text.data(), text.size(), nullptr, &from_json), DC_OK) << dc_last_error();
    void* data = nullptr;
    std::size_t size = 0;
    ASSERT_EQ(dc_meshes_write_memory(from_json, DC_FORMAT_BINARY, 0, &data, &size), DC_OK);
    dc_meshes* from_binary = nullptr;
    ASSERT_EQ(dc_meshes_read_memory(data, size, nullptr, &from_binary), DC_OK) << dc_last_error();
    dc_free(data);
    for (const dc_meshes* m : {from_json, from_binary}) {
        ASSERT_EQ(dc_meshes_animation_count(m), 1u);
        ASSERT_EQ(dc_meshes_animation_frame_count(m, 0), 2u);
        EXPECT_EQ(dc_meshes_animation_frame_count(m, 1), 0u);
        dc_animation_frame f{};
        ASSERT_EQ(dc_meshes_animation_frame(m, 0, 1, &f), DC_OK);
        EXPECT_EQ(f.image, 0u);
        EXPECT_EQ(f.rect.x, 2);
        EXPECT_EQ(f.rect.w, 2);
        EXPECT_EQ(f.duration_ms, 50);
        EXPECT_EQ(dc_meshes_animation_frame(m, 0, 2, &f), DC_ERROR_INVALID_ARGUMENT);
        EXPECT_EQ(dc_meshes_animation_frame(m, 1, 0, &f), DC_ERROR_INVALID_ARGUMENT);
        ASSERT_EQ(dc_meshes_animated_run_count(m), 1u);
        dc_animated_run r{};
        ASSERT_EQ(dc_meshes_animated_run(m, 0, &r), DC_OK);
        EXPECT_EQ(r.draw, 0u);
        EXPECT_EQ(r.first_vertex, 1u);
        EXPECT_EQ(r.vertex_count, 2u);
        EXPECT_EQ(r.animation, 0u);
        EXPECT_EQ(dc_meshes_animated_run(m, 1, &r), DC_ERROR_INVALID_ARGUMENT);
        EXPECT_EQ(dc_meshes_animated_run(m, 0, nullptr), DC_ERROR_INVALID_ARGUMENT);
    }
    EXPECT_EQ(dc_meshes_animation_count(nullptr), 0u);
    EXPECT_EQ(dc_meshes_animated_run_count(nullptr), 0u);
    dc_meshes_destroy(from_binary);
    dc_meshes_destroy(from_json);
}

} // namespace
} // namespace depthcull::test
