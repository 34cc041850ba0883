// Memory from small files (issue 21, point 6): decoded images, the
// analysis' scratch memory, workers together and animations are bounded
// by documented limits checked before anything large is allocated, and
// every such error names the file and the limit. Each test failed before:
// images were decoded per entry and all held, nothing estimated the
// analysis, -j multiplied its memory and animations had no texel bound.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <jpeglib.h>

#include "depthcull/io.h"
#include "depthcull/limits.h"
#include "depthcull/pipeline.h"
#include "pipeline/parallel.h"
#include "test_scene_json_helpers.h"

#include "testing/io_error.h"

namespace depthcull::test {
namespace {

namespace fs = std::filesystem;

// A PNG that is only its signature, IHDR and IEND: its header says
// width x height, and it holds no pixels. Checks on headers refuse it
// before a decode would find it empty.
std::string png_header_only(std::uint32_t width, std::uint32_t height) {
    auto be32 = [](std::string& s, std::uint32_t v) {
        for (int shift = 24; shift >= 0; shift -= 8) s.push_back(char((v >> shift) & 0xff));
    };
    auto chunk = [&](std::string& s, const std::string& type, const std::string& data) {
        be32(s, std::uint32_t(data.size()));
        const std::string body = type + data;
        s += body;
        be32(s, std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()))));
    };
    std::string ihdr;
    be32(ihdr, width);
    be32(ihdr, height);
    ihdr += std::string("\x08\x06\x00\x00\x00", 5); // RGBA8
    std::string png = "\x89PNG\r\n\x1a\n";
    chunk(png, "IHDR", ihdr);
    chunk(png, "IEND", "");
    return png;
}

Image opaque_image(int w, int h) {
    Image image;
    image.width = w;
    image.height = h;
    image.rgba.assign(std::size_t(w) * std::size_t(h) * 4, 255);
    return image;
}

// ---- 6a: one decode per (file, colour key), only what is shown

TEST(MemoryLimits, OneDecodePerFileAndColourKeyOnlyForShownImages) {
    SceneDir dir("mem_decode_once");
    dir.standard_art();
    fs::create_symlink(fs::path(dir.path("art/blob.png")), dir.path("art/link.png"));
    const std::string scene = dir.write("s.json", R"({"images": [
        {"id": "a", "path": "art/blob.png"}, {"id": "b", "path": "art/./blob.png"}, {"id": "c", "path": "art/link.png"},
        {"id": "k", "path": "art/blob.png", "trans": "ff00ff"}, {"id": "unused", "path": "art/tiles.png"}],
        "elements": [{"image": "a"}, {"image": "b"}, {"image": "c"}, {"image": "k"}]})");
    const pipeline::PreparedScene p = pipeline::prepare_scene(scene, {});
    ASSERT_EQ(p.pixels.size(), 5u);
    EXPECT_EQ(p.decoded.size(), 2u); // blob plain and blob keyed; tiles never
    EXPECT_EQ(p.pixels[0], p.pixels[1]);
    EXPECT_EQ(p.pixels[0], p.pixels[2]);
    EXPECT_NE(p.pixels[0], p.pixels[3]);
    EXPECT_EQ(p.pixels[4], pipeline::PreparedScene::kNotDecoded);
    EXPECT_EQ(p.view(0).width, 8);
    EXPECT_EQ(p.view(4).width, 1); // the placeholder renderers upload
    EXPECT_EQ(p.views().size(), 5u);
    // Shared pixels give the same analysis as before: one per (file, rect).
    EXPECT_EQ(p.analysis.images.size(), 2u);
}

TEST(MemoryLimits, DecodedImagesAreBoundedOnTheirHeadersNamingEntryFileAndLimit) {
    SceneDir dir("mem_decoded_total");
    dir.standard_art();
    const std::string scene = dir.write("s.json", R"({"images": [{"id": "a", "path": "art/blob.png"}, {"id": "b", "path": "art/tiles.png"},
        {"id": "big", "path": "art/big.png"}], "elements": [{"image": "a"}, {"image": "b"}]})");
    // An unshown image is not counted, even one far over the limit.
    std::ofstream(dir.path("art/big.png"), std::ios::binary) << png_header_only(16384, 16384);
    pipeline::PrepareOptions o;
    o.max_decoded_bytes = 8 * 8 * 4 + 16 * 8 * 4;
    EXPECT_EQ(pipeline::prepare_scene(scene, o).decoded.size(), 2u);
    o.max_decoded_bytes -= 1;
    const std::string e = io_error([&] { pipeline::prepare_scene(scene, o); });
    EXPECT_TRUE(has(e, "s.json: image 1 \"b\" (" + dir.path("art/tiles.png") + ")")) << e;
    EXPECT_TRUE(has(e, "kMaxDecodedBytes")) << e;
}

TEST(MemoryLimits, GiantHeadersNamedByManyEntriesAreRefusedBeforeDecoding) {
    // Three 16384^2 files (3 GiB decoded) from a few hundred bytes: over
    // kMaxDecodedBytes on their headers alone. One file named by three
    // entries (two spellings and a symlink) is one decode and fits.
    SceneDir dir("mem_giant_headers");
    for (const char* name : {"art/g1.png", "art/g2.png", "art/g3.png"})
        std::ofstream(dir.path(name), std::ios::binary) << png_header_only(16384, 16384);
    fs::create_symlink(fs::path(dir.path("art/g1.png")), dir.path("art/g1-link.png"));
    const std::string three = dir.write("three.json", R"({"images": [{"id": "a", "path": "art/g1.png"}, {"id": "b", "path": "art/g2.png"},
        {"id": "c", "path": "art/g3.png"}], "elements": [{"image": "a"}, {"image": "b"}, {"image": "c"}]})");
    const std::string e = io_error([&] { pipeline::prepare_scene(three, {}); });
    EXPECT_TRUE(has(e, "three.json: image 2 \"c\"")) << e;
    EXPECT_TRUE(has(e, "g3.png")) << e;
    EXPECT_TRUE(has(e, "over the limit of 2048 MiB (kMaxDecodedBytes)")) << e;
    const std::string one = dir.write("one.json", R"({"images": [{"id": "a", "path": "art/g1.png"}, {"id": "b", "path": "art/./g1.png"},
        {"id": "c", "path": "art/g1-link.png"}], "elements": [{"image": "a"}, {"image": "b"}, {"image": "c"}]})");
    // Past the total check, the one decode finds no pixels in the file.
    EXPECT_FALSE(has(io_error([&] { pipeline::prepare_scene(one, {}); }), "kMaxDecodedBytes"));
}

// ---- 6d: the analysis' scratch memory, estimated before it runs

TEST(MemoryLimits, CoreRefusesAnAnalysisOverItsScratchLimitAndThrowsNothing) {
    const Image image = opaque_image(64, 48);
    const AnalyzeOptions options;
    const std::uint64_t need = analysis_scratch_bytes(image.view().bounds(), options);
    EXPECT_GT(need, std::uint64_t(64 * 48));
    ImageAnalysis out;
    EXPECT_EQ(analyze_image(image.view(), image.view().bounds(), options, need - 1, out), AnalyzeStatus::over_memory_limit);
    EXPECT_TRUE(out.boundary.empty());
    ASSERT_EQ(analyze_image(image.view(), image.view().bounds(), options, need, out), AnalyzeStatus::ok);
    EXPECT_EQ(out, analyze_image(image.view(), image.view().bounds(), options));
    // The documented limit: an 8192^2 opaque image fits, the largest one
    // (about 8 GiB of search) does not.
    EXPECT_LE(analysis_scratch_bytes({0, 0, 8192, 8192}, options), kMaxAnalysisBytes);
    EXPECT_GT(analysis_scratch_bytes({0, 0, kMaxImageSide, kMaxImageSide}, options), kMaxAnalysisBytes);
}

TEST(MemoryLimits, AnAnalysisOverTheBudgetNamesFileRectAndLimit) {
    SceneDir dir("mem_analysis_limit");
    io::write_png(dir.path("art/wall.png"), opaque_image(96, 64).view());
    const std::string scene =
        dir.write("s.json", R"({"images": [{"id": "w", "path": "art/wall.png"}], "elements": [{"image": "w", "rect": [8, 0, 80, 64]}]})");
    pipeline::MemoryBudget small(analysis_scratch_bytes({8, 0, 80, 64}, {}) - 1);
    pipeline::PrepareOptions o;
    o.memory = &small;
    const std::string e = io_error([&] { pipeline::prepare_scene(scene, o); });
    EXPECT_TRUE(has(e, "s.json: image 0 \"w\" (" + dir.path("art/wall.png") + "): rect 8,0 80x64")) << e;
    EXPECT_TRUE(has(e, "(kMaxAnalysisBytes)")) << e;
    EXPECT_EQ(small.peak(), 0u); // refused before anything was reserved
}

TEST(MemoryLimits, AJpegHeaderOverTheAnalysisLimitIsRefusedBeforeDecoding) {
    // A real baseline JPEG from libjpeg, its SOF0 size rewritten to
    // 16384^2: a few hundred bytes that decode to 1 GiB and would need
    // about 8 GiB of opaque search.
    jpeg_compress_struct c{};
    jpeg_error_mgr err{};
    c.err = jpeg_std_error(&err);
    jpeg_create_compress(&c);
    unsigned char* buffer = nullptr;
    unsigned long size = 0;
    jpeg_mem_dest(&c, &buffer, &size);
    c.image_width = c.image_height = 8;
    c.input_components = 3;
    c.in_color_space = JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_start_compress(&c, TRUE);
    std::vector<unsigned char> row(8 * 3, 200);
    while (c.next_scanline < c.image_height) {
        JSAMPROW r = row.data();
        jpeg_write_scanlines(&c, &r, 1);
    }
    jpeg_finish_compress(&c);
    std::string jpeg(reinterpret_cast<char*>(buffer), size);
    jpeg_destroy_compress(&c);
    std::free(buffer);
    const std::size_t sof = jpeg.find("\xff\xc0");
    ASSERT_NE(sof, std::string::npos);
    jpeg[sof + 5] = '\x40', jpeg[sof + 6] = '\x00', jpeg[sof + 7] = '\x40', jpeg[sof + 8] = '\x00';
    SceneDir dir("mem_jpeg_header");
    const std::string path = dir.path("art/wall.jpg");
    std::ofstream(path, std::ios::binary) << jpeg;
    int w = 0, h = 0;
    io::image_size(path, &w, &h);
    ASSERT_EQ(w, 16384);
    const std::string e = io_error([&] { pipeline::check_analysis_memory(path, {0, 0, w, h}, {}); });
    EXPECT_TRUE(has(e, path + ": rect 0,0 16384x16384: analysing it needs about")) << e;
    EXPECT_TRUE(has(e, "over the limit of 2048 MiB (kMaxAnalysisBytes)")) << e;
}

TEST(MemoryLimits, MultipackPagesAreBoundedOnTheirHeaders) {
    // Three pages naming one 16384^2 header-only PNG: 3 GiB if decoded.
    SceneDir dir("mem_multipack");
    std::ofstream(dir.path("art/page.png"), std::ios::binary) << png_header_only(16384, 16384);
    std::string textures;
    for (int i = 0; i < 3; ++i)
        textures += std::string(i ? "," : "") + R"({"image": "art/page.png", "size": {"w": 16384, "h": 16384}, "frames": [{"filename": "f)" +
                    std::to_string(i) + R"(", "frame": {"x": 0, "y": 0, "w": 8, "h": 8}}]})";
    const std::string atlas = dir.write("m.json", "{\"textures\": [" + textures + "]}");
    const std::string e = io_error([&] { pipeline::atlas_with_polygons(atlas, {}); });
    EXPECT_TRUE(has(e, "m.json: page " + dir.path("art/page.png"))) << e;
    EXPECT_TRUE(has(e, "(kMaxDecodedBytes)")) << e;
}

// ---- 6e: workers share one budget; output as with one thread

TEST(MemoryLimits, WorkersReserveFromOneBudgetAndOutputMatchesOneThread) {
    SceneDir dir("mem_workers");
    std::string images, elements;
    for (int i = 0; i < 8; ++i) {
        Image image = opaque_image(64, 64);
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x)
                if ((x - 32) * (x - 32) + (y - 32) * (y - 32) > (20 + 2 * i) * (20 + 2 * i)) image.rgba[std::size_t(y * 64 + x) * 4 + 3] = 0;
        io::write_png(dir.path("art/" + std::to_string(i) + ".png"), image.view());
        images += std::string(i ? "," : "") + R"({"id": ")" + std::to_string(i) + R"(", "path": "art/)" + std::to_string(i) + R"(.png"})";
        elements += std::string(i ? "," : "") + R"({"image": ")" + std::to_string(i) + R"("})";
    }
    const std::string scene = dir.write("s.json", "{\"images\": [" + images + "], \"elements\": [" + elements + "]}");
    const std::uint64_t one = analysis_scratch_bytes({0, 0, 64, 64}, {});
    pipeline::MemoryBudget budget(2 * one + one / 2); // two analyses at a time, whatever -j
    pipeline::PrepareOptions eight;
    eight.threads = 8;
    eight.memory = &budget;
    const pipeline::PreparedScene many = pipeline::prepare_scene(scene, eight);
    EXPECT_GE(budget.peak(), one);
    EXPECT_LE(budget.peak(), 2 * one);
    pipeline::PrepareOptions serial;
    serial.threads = 1;
    const pipeline::PreparedScene single = pipeline::prepare_scene(scene, serial);
    ASSERT_EQ(many.analysis.images.size(), 8u);
    EXPECT_EQ(many.analysis.images, single.analysis.images);
}

TEST(MemoryLimits, BudgetHoldsAreReleasedAndWaitersProceed) {
    pipeline::MemoryBudget budget(100);
    std::vector<std::size_t> order;
    std::mutex m;
    pipeline::parallel_for(16, 8, [&](std::size_t i) {
        pipeline::MemoryBudget::Hold hold = budget.reserve(40 + i % 3 * 10);
        std::lock_guard lock(m);
        order.push_back(i);
    });
    EXPECT_EQ(order.size(), 16u);
    EXPECT_LE(budget.peak(), 100u);
    pipeline::MemoryBudget::Hold all = budget.reserve(100); // everything was given back
    EXPECT_EQ(budget.peak(), 100u);
}

// ---- 6f: animations

TEST(MemoryLimits, AnimationTexelsAreBoundedBeforeDecoding) {
    // 65 frames of one 4096^2 tile: 65 * 2^24 texels, over 2^30, from a
    // header-only PNG and a map of a few KB.
    SceneDir dir("mem_animation");
    std::ofstream(dir.path("sheet.png"), std::ios::binary) << png_header_only(4096, 4096);
    std::string frames;
    for (int i = 0; i < 65; ++i) frames += "<frame tileid=\"0\" duration=\"10\"/>";
    const std::string map = dir.write("a.tmx", "<map orientation=\"orthogonal\" width=\"1\" height=\"1\" tilewidth=\"4096\" tileheight=\"4096\">"
                                               "<tileset firstgid=\"1\" name=\"a\" tilewidth=\"4096\" tileheight=\"4096\"><image source=\"sheet.png\"/>"
                                               "<tile id=\"0\"><animation>" + frames + "</animation></tile>"
                                               "</tileset><layer name=\"g\" width=\"1\" height=\"1\"><data encoding=\"csv\">1</data></layer></map>");
    const std::string e = io_error([&] { pipeline::prepare_scene(map, {}); });
    EXPECT_TRUE(has(e, "a.tmx: image 0")) << e;
    EXPECT_TRUE(has(e, "sheet.png")) << e;
    EXPECT_TRUE(has(e, "65 frames of 4096x4096")) << e;
    EXPECT_TRUE(has(e, "(kMaxAnimationTexels)")) << e;
}

} // namespace
} // namespace depthcull::test
