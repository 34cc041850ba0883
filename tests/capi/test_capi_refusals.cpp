// The C API refuses what its C++ counterparts refuse, with a message
// naming the culprit: sprites out of an element's ranges, a picture with
// another rect's analysis, counts past a frame's limit, animations of no
// or unknown pictures, and write paths that name no file.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include "depthcull/depthcull.h"

namespace {

// A 16x16 texture whose left half is transparent, the right opaque.
struct Texture {
    std::vector<std::uint8_t> rgba = std::vector<std::uint8_t>(16 * 16 * 4, 255);
    Texture() {
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 8; ++x) rgba[std::size_t((y * 16 + x) * 4 + 3)] = 0;
    }
    dc_analysis* analyze(dc_rect rect) const {
        dc_analysis* a = nullptr;
        EXPECT_EQ(dc_analyze_image(rgba.data(), 16, 16, 64, rect, nullptr, &a), DC_OK) << dc_last_error();
        return a;
    }
};

struct Assembler {
    Texture texture;
    dc_analysis* opaque = texture.analyze({8, 0, 8, 8});
    dc_assembler* assembler = nullptr;
    dc_frame* frame = nullptr;
    uint32_t picture = 0;
    Assembler() {
        EXPECT_EQ(dc_assembler_create(&assembler), DC_OK);
        EXPECT_EQ(dc_frame_create(&frame), DC_OK);
        EXPECT_EQ(dc_assembler_add_image(assembler, 0, 16, 16, {8, 0, 8, 8}, opaque, &picture), DC_OK) << dc_last_error();
    }
    ~Assembler() {
        dc_frame_destroy(frame);
        dc_assembler_destroy(assembler);
        dc_analysis_destroy(opaque);
    }
    dc_sprite sprite(double x = 0) const {
        dc_sprite s;
        dc_sprite_default(&s);
        s.image = picture;
        s.transform[4] = x;
        return s;
    }
};

// Before: 1e300 (or a scale of 1e39) made Infinity vertices, colours 5 and
// -1 went into the vertices as they were, all DC_OK.
TEST(CApiRefusals, SpritesOutsideAnElementsRangesAreRefusedByName) {
    Assembler a;
    struct Case {
        int transform, color;
        double value;
        const char* message;
    };
    const Case cases[] = {
        {4, -1, 1e300, "dc_assemble: sprite 1: transform[4] 1e+300 is not a finite number within +-1e9 (kMaxCoordinate)"},
        {0, -1, 1e39, "dc_assemble: sprite 1: transform[0] 1e+39 is not a finite number within +-1e9 (kMaxCoordinate)"},
        {3, -1, -2e9, "dc_assemble: sprite 1: transform[3] -2000000000 is not a finite number within +-1e9 (kMaxCoordinate)"},
        {-1, 0, 5, "dc_assemble: sprite 1: color[0] 5 is not in 0..1"},
        {-1, 3, -1, "dc_assemble: sprite 1: color[3] -1 is not in 0..1"},
        {-1, 1, NAN, "dc_assemble: sprite 1: color[1] nan is not in 0..1"},
    };
    for (const Case& c : cases) {
        dc_sprite sprites[2] = {a.sprite(0), a.sprite(4)};
        if (c.transform >= 0) sprites[1].transform[c.transform] = c.value;
        else sprites[1].color[c.color] = float(c.value);
        EXPECT_EQ(dc_assemble(a.assembler, sprites, 2, {0, 0, 64, 64}, a.frame), DC_ERROR_INVALID_ARGUMENT) << c.message;
        EXPECT_STREQ(dc_last_error(), c.message);
        size_t vertices = 1;
        dc_frame_vertices(a.frame, &vertices);
        EXPECT_EQ(vertices, 0u);
    }
    // dc_scene_add_element's ranges, edges included.
    dc_sprite edge = a.sprite(1e9);
    edge.transform[0] = -1e9;
    edge.color[0] = 0;
    ASSERT_EQ(dc_assemble(a.assembler, &edge, 1, {0, 0, 64, 64}, a.frame), DC_OK) << dc_last_error();
    size_t count = 0;
    const float* v = dc_frame_vertices(a.frame, &count);
    ASSERT_GT(count, 0u);
    for (size_t k = 0; k < count * DC_VERTEX_FLOATS; ++k) EXPECT_TRUE(std::isfinite(v[k]));
    // An unknown picture or animation, a blend that is no dc_blend: named too.
    dc_sprite other = a.sprite();
    other.image = 9;
    EXPECT_EQ(dc_assemble(a.assembler, &other, 1, {0, 0, 64, 64}, a.frame), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_assemble: sprite 0: image 9 is not an add_image id");
    other = a.sprite();
    other.animation = 2;
    EXPECT_EQ(dc_assemble(a.assembler, &other, 1, {0, 0, 64, 64}, a.frame), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_assemble: sprite 0: animation 2 is not an add_animation id");
}

// Before: accepted, and the opaque picture drew the transparent rect's
// polygons: nothing. dc_scene_add_element refuses the same mismatch.
TEST(CApiRefusals, APictureNeedsTheAnalysisOfItsRect) {
    Assembler a;
    dc_analysis* transparent = a.texture.analyze({0, 0, 8, 8});
    uint32_t id = 77;
    EXPECT_EQ(dc_assembler_add_image(a.assembler, 0, 16, 16, {8, 0, 8, 8}, transparent, &id), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_assembler_add_image: the analysis is of another rect (0, 0, 8x8) than the picture's (8, 0, 8x8)");
    EXPECT_EQ(id, 77u);
    // The other causes keep their own messages.
    EXPECT_EQ(dc_assembler_add_image(a.assembler, 0, 16, 16, {12, 0, 8, 8}, a.opaque, &id), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_assembler_add_image: rect is outside the texture");
    EXPECT_EQ(dc_assembler_add_image(a.assembler, 0, 0, 16, {8, 0, 8, 8}, a.opaque, &id), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_assembler_add_image: texture size is not positive");
    // The matching analysis: the opaque 8x8 picture draws (the other
    // analysis drew 0 triangles).
    dc_sprite s = a.sprite();
    ASSERT_EQ(dc_assemble(a.assembler, &s, 1, {0, 0, 64, 64}, a.frame), DC_OK) << dc_last_error();
    dc_frame_stats stats;
    ASSERT_EQ(dc_frame_stats_get(a.frame, &stats), DC_OK);
    EXPECT_EQ(stats.triangles, 4);
    dc_analysis_destroy(transparent);
}

// Before: SIZE_MAX was DC_ERROR_INTERNAL "vector::reserve", 2^40 tried to
// allocate (DC_ERROR_OUT_OF_MEMORY), and animations of no or unknown
// pictures said "bad picture: empty rect, ...".
TEST(CApiRefusals, ReserveAndAnimationsSayWhatIsWrong) {
    Assembler a;
    const std::string most = "2097151";
    for (size_t sprites : {SIZE_MAX, size_t(1) << 40, size_t(2097152)}) {
        EXPECT_EQ(dc_assembler_reserve(a.assembler, sprites, a.frame), DC_ERROR_INVALID_ARGUMENT);
        EXPECT_EQ(std::string(dc_last_error()), "dc_assembler_reserve: " + std::to_string(sprites) + " sprites are more than a frame holds (" + most +
                                                    ", one depth level each: kMaxDepthLevels)");
    }
    EXPECT_EQ(dc_assembler_reserve(a.assembler, 64, a.frame), DC_OK) << dc_last_error();

    const uint32_t frames[3] = {a.picture, a.picture, 7};
    uint32_t id = 0;
    EXPECT_EQ(dc_assembler_add_animation(a.assembler, frames, 0, &id), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_assembler_add_animation: count is 0: an animation shows at least one picture");
    EXPECT_EQ(dc_assembler_add_animation(a.assembler, frames, 3, &id), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_assembler_add_animation: frame 2: image 7 is not a dc_assembler_add_image id (the assembler has 1)");
    const uint32_t huge[1] = {UINT32_MAX};
    EXPECT_EQ(dc_assembler_add_animation(a.assembler, huge, 1, &id), DC_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(dc_last_error(), "dc_assembler_add_animation: frame 0: image 4294967295 is not a dc_assembler_add_image id (the assembler has 1)");
    EXPECT_EQ(dc_assembler_add_animation(a.assembler, frames, 2, &id), DC_OK) << dc_last_error();
}

// Before: "" and "-" were the io writers' standard output: DC_OK, and the
// meshes went into the host process's stdout.
TEST(CApiRefusals, WriteFileNeedsAFileName) {
    dc_meshes* m = nullptr;
    ASSERT_EQ(dc_meshes_create(&m), DC_OK);
    for (const char* path : {"", "-"}) {
        for (dc_format format : {DC_FORMAT_JSON, DC_FORMAT_BINARY}) {
            testing::internal::CaptureStdout();
            const dc_status status = dc_meshes_write_file(m, path, format, 0);
            const std::string out = testing::internal::GetCapturedStdout();
            EXPECT_EQ(status, DC_ERROR_INVALID_ARGUMENT) << '"' << path << '"';
            EXPECT_EQ(out, "");
            EXPECT_EQ(std::string(dc_last_error()), std::string("dc_meshes_write_file: path \"") + path +
                                                        "\" names no file (for a file named \"-\", pass \"./-\"; for bytes in memory, "
                                                        "dc_meshes_write_memory)");
        }
    }
    // A file named "-" in a directory is a file like any other.
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("dc_refusals_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    const std::string dash = (dir / "-").string();
    EXPECT_EQ(dc_meshes_write_file(m, dash.c_str(), DC_FORMAT_JSON, 0), DC_OK) << dc_last_error();
    dc_meshes* back = nullptr;
    EXPECT_EQ(dc_meshes_read_file(dash.c_str(), &back), DC_OK) << dc_last_error();
    dc_meshes_destroy(back);
    std::filesystem::remove_all(dir);
    dc_meshes_destroy(m);
}

} // namespace
