// Memory from small files through the CLI with the real limits (issue 21,
// point 6): only header checks, so each run is cheap. Both failed before:
// analyze decoded the JPEG to 1 GiB and its search ran out of memory with
// "out of memory" naming no file; optimize decoded each 1 GiB image.
#include <gtest/gtest.h>
#include <zlib.h>

#include "run_cli.h"

namespace depthcull::test {
namespace {

std::string png_header_only(std::uint32_t w, std::uint32_t h) {
    auto be32 = [](std::string& s, std::uint32_t v) {
        for (int shift = 24; shift >= 0; shift -= 8) s.push_back(char((v >> shift) & 0xff));
    };
    std::string ihdr;
    be32(ihdr, w);
    be32(ihdr, h);
    ihdr += std::string("\x08\x06\x00\x00\x00", 5);
    std::string png = "\x89PNG\r\n\x1a\n";
    be32(png, 13);
    const std::string body = "IHDR" + ihdr;
    png += body;
    be32(png, std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(body.data()), uInt(body.size()))));
    return png;
}

TEST(MemoryCli, AnalyzeRefusesAJpegHeaderOverTheAnalysisLimitNamingTheFile) {
    // SOI, a quantization table, SOF0 of 16384x16384 grey, SOS, EOI: under
    // a hundred bytes.
    std::string jpeg = "\xff\xd8\xff\xdb";
    jpeg += std::string("\x00\x43\x00", 3) + std::string(64, '\x01');
    jpeg += std::string("\xff\xc0\x00\x0b\x08\x40\x00\x40\x00\x01\x01\x11\x00", 13);
    jpeg += std::string("\xff\xda\x00\x08\x01\x01\x00\x00\x3f\x00\xff\xd9", 12);
    const auto dir = scratch_dir("memory_cli_jpeg");
    std::ofstream(dir / "giant.jpg", std::ios::binary) << jpeg;
    const CliResult r = run_cli("analyze " + shell_quote(dir / "giant.jpg") + " --no-cache -o " + shell_quote(dir / "a.json"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find((dir / "giant.jpg").string() + ": rect 0,0 16384x16384: analysing it needs about"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("over the limit of 2048 MiB (kMaxAnalysisBytes)"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "a.json"));
    std::filesystem::remove_all(dir);
}

TEST(MemoryCli, OptimizeRefusesDecodesOverTheTotalOnTheirHeaders) {
    const auto dir = scratch_dir("memory_cli_decoded");
    for (const char* name : {"g1.png", "g2.png", "g3.png"}) std::ofstream(dir / name, std::ios::binary) << png_header_only(16384, 16384);
    std::ofstream(dir / "s.json") << R"({"images": [{"id": "a", "path": "g1.png"}, {"id": "b", "path": "g2.png"}, {"id": "c", "path": "g3.png"}],
        "elements": [{"image": "a"}, {"image": "b"}, {"image": "c"}]})";
    const CliResult r = run_cli("optimize " + shell_quote(dir / "s.json") + " --no-cache -o " + shell_quote(dir / "out.json"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("s.json: image 2 \"c\" (" + (dir / "g3.png").string() + "): 16384x16384 brings the decoded images to 3072 MiB, "
                         "over the limit of 2048 MiB (kMaxDecodedBytes)"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.json"));
    std::filesystem::remove_all(dir);
}

} // namespace
} // namespace depthcull::test
