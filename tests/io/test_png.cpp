#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <png.h>

#include "depthcull/io.h"
#include "testing/ascii_image.h"

using namespace depthcull;

namespace {

// Writes a PNG of the given libpng colour type with the low-level API, so
// the loader is tested against every kind of file a user may have.
std::string write_png(int color_type, int bit_depth, int w, int h, const std::vector<std::uint8_t>& rows_bytes,
                      const std::vector<png_color>& palette = {}, const std::vector<png_byte>& trns = {}) {
    std::string path = (std::filesystem::temp_directory_path() / ("dc_png_" + std::to_string(color_type) + "_" +
                                                                   std::to_string(bit_depth) + ".png")).string();
    FILE* f = std::fopen(path.c_str(), "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, w, h, bit_depth, color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (!palette.empty()) png_set_PLTE(png, info, palette.data(), int(palette.size()));
    if (!trns.empty()) png_set_tRNS(png, info, trns.data(), int(trns.size()), nullptr);
    png_write_info(png, info);
    std::size_t stride = rows_bytes.size() / h;
    for (int y = 0; y < h; ++y) png_write_row(png, rows_bytes.data() + y * stride);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    return path;
}

} // namespace

TEST(Png, RoundTripRgba) {
    Image img = test::ascii_image({"#.+", "+#."});
    std::string path = (std::filesystem::temp_directory_path() / "dc_roundtrip.png").string();
    io::write_png(path, img.view());
    Image back = io::read_png(path);
    EXPECT_EQ(back.width, 3);
    EXPECT_EQ(back.height, 2);
    EXPECT_EQ(back.rgba, img.rgba);
}

TEST(Png, GreyIsOpaque) {
    Image img = io::read_png(write_png(PNG_COLOR_TYPE_GRAY, 8, 2, 1, {10, 200}));
    EXPECT_EQ(img.rgba[3], 255);
    EXPECT_EQ(img.rgba[4], 200);
}

TEST(Png, PaletteWithTrns) {
    Image img = io::read_png(write_png(PNG_COLOR_TYPE_PALETTE, 8, 3, 1, {0, 1, 2}, {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}}, {0, 128}));
    EXPECT_EQ(img.rgba[3], 0);
    EXPECT_EQ(img.rgba[7], 128);
    EXPECT_EQ(img.rgba[11], 255);
    EXPECT_EQ(img.rgba[5], 255); // green of texel 1 (palette entry 1)
}

TEST(Png, SixteenBitRgbaKeepsAlphaClasses) {
    // Two texels: alpha 0xFFFF and 0x0000 (big-endian 16-bit samples).
    std::vector<std::uint8_t> row{0x12, 0x34, 0x56, 0x78, 0x9a, 0xbc, 0xff, 0xff, 0, 0, 0, 0, 0, 0, 0, 0};
    Image img = io::read_png(write_png(PNG_COLOR_TYPE_RGBA, 16, 2, 1, row));
    EXPECT_EQ(img.rgba[3], 255);
    EXPECT_EQ(img.rgba[7], 0);
}

TEST(Png, RgbIsOpaque) {
    Image img = io::read_png(write_png(PNG_COLOR_TYPE_RGB, 8, 1, 1, {1, 2, 3}));
    EXPECT_EQ(img.rgba, (std::vector<std::uint8_t>{1, 2, 3, 255}));
}

TEST(Png, CorruptAndMissingFilesGiveOneLineErrors) {
    std::string path = (std::filesystem::temp_directory_path() / "dc_corrupt.png").string();
    std::ofstream(path) << "not a png at all";
    try {
        io::read_png(path);
        FAIL();
    } catch (const depthcull::Error& e) {
        std::string m = e.what();
        EXPECT_NE(m.find(path), std::string::npos);
        EXPECT_EQ(m.find('\n'), std::string::npos);
    }
    EXPECT_THROW(io::read_png("/nonexistent/x.png"), depthcull::Error);
}

TEST(Png, TruncatedFileIsAnError) {
    Image img = test::ascii_image({"####", "####", "####"});
    std::string bytes = io::encode_png(img.view());
    bytes.resize(bytes.size() - 20);
    EXPECT_THROW(io::decode_png(bytes.data(), bytes.size(), "t.png"), depthcull::Error);
}

TEST(AtomicWrite, ReplacesAndLeavesNoTemporaries) {
    auto dir = std::filesystem::temp_directory_path() / "dc_atomic";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    std::string path = (dir / "out.txt").string();
    io::write_file_atomic(path, "one");
    io::write_file_atomic(path, "two");
    EXPECT_EQ(io::read_file(path), "two");
    int files = 0;
    for (auto& e : std::filesystem::directory_iterator(dir)) (void)e, ++files;
    EXPECT_EQ(files, 1);
    EXPECT_THROW(io::write_file_atomic((dir / "missing" / "x").string(), "x"), depthcull::Error);
}

// Output written in pieces as it is made: the pieces in order, and a
// producer that fails half-way leaves the old file and no temporary.
TEST(AtomicWrite, StreamedPiecesOrAFailingProducerLeaveNoHalfFile) {
    auto dir = std::filesystem::temp_directory_path() / "dc_atomic_stream";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "out.txt").string();
    io::write_file_atomic(path, [](const io::WriteBytes& write) {
        write("one ");
        write("two");
    });
    EXPECT_EQ(io::read_file(path), "one two");
    EXPECT_THROW(io::write_file_atomic(path,
                                       [](const io::WriteBytes& write) {
                                           write("half");
                                           throw depthcull::Error("out.txt: made up");
                                       }),
                 depthcull::Error);
    EXPECT_EQ(io::read_file(path), "one two");
    int files = 0;
    for (auto& e : std::filesystem::directory_iterator(dir)) (void)e, ++files;
    EXPECT_EQ(files, 1);
}

// libpng allocates a chunk's declared length before reading it: a 51-byte
// file whose text chunk said 2 GiB took 2 GiB (and 12 s) before "file ends
// early". Chunks before the image data must fit in the file; what follows
// it (no png_read_end) is not read, so a broken trailing chunk still loads.
TEST(Png, ChunkLongerThanTheFileIsRefusedBeforeLibpngAllocatesIt) {
    Image img = test::ascii_image({"##", "#."});
    const std::string good = io::encode_png(img.view());
    auto chunk_header = [](std::uint32_t length, const char* type) {
        std::string h{char(length >> 24), char(length >> 16), char(length >> 8), char(length)};
        return h + type;
    };
    std::string bytes = good.substr(0, 33) + chunk_header(0x7fffffffu, "tEXt") + "0123456789" + good.substr(33);
    try {
        io::decode_png(bytes.data(), bytes.size(), "text.png");
        FAIL();
    } catch (const depthcull::Error& e) {
        EXPECT_NE(std::string(e.what()).find("text.png: corrupt PNG (chunk 'tEXt' at byte 33 says 2147483647 bytes"), std::string::npos)
            << e.what();
    }
    const std::size_t iend = good.size() - 12;
    std::string trailing = good.substr(0, iend) + chunk_header(0x7fffffffu, "tEXt") + "abc";
    EXPECT_EQ(io::decode_png(trailing.data(), trailing.size(), "trailing.png").rgba, img.rgba);
}
