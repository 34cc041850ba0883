// Issue 21, point 1 through the command line: files engines load give a
// `warning:` line naming the file, the frame and what was assumed, exit 0;
// --strict (analyze, atlas, and every command reading a scene) makes the
// same line an error, exit 1; warnings come in input order whatever the
// thread count. Every file is made here.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "cli/run_cli.h"
#include "depthcull/io.h"
#include "testing/ascii_image.h"
#include "testing/image_files.h"

using namespace depthcull;
using depthcull::test::run_cli;
using depthcull::test::shell_quote;
namespace fs = std::filesystem;

namespace {

std::string write(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
    return path.string();
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

int lines_starting(const std::string& text, const std::string& prefix) {
    int n = 0;
    for (std::size_t at = 0; at < text.size();) {
        const std::size_t end = text.find('\n', at);
        if (text.compare(at, prefix.size(), prefix) == 0) ++n;
        if (end == std::string::npos) break;
        at = end + 1;
    }
    return n;
}

} // namespace

TEST(RealFilesCli, AtlasWhosePageWasResavedSmallerWarnsAndStrictRefuses) {
    const fs::path dir = test::scratch_dir("real_atlas");
    io::write_png((dir / "page.png").string(), test::ascii_image(std::vector<std::string>(16, std::string(16, '#'))).view());
    const std::string atlas = write(dir / "sheet.json",
                                    R"({"frames": {"a": {"frame": {"x": 0, "y": 0, "w": 8, "h": 8}},
                                        "b": {"frame": {"x": 8, "y": 8, "w": 8, "h": 8}, "spriteSourceSize": {"x": 3, "y": 0, "w": 8, "h": 8},
                                              "sourceSize": {"w": 10, "h": 8}}},
                                        "meta": {"image": "page.png", "size": {"w": 32, "h": 32}, "scale": "0.5"}})");
    auto r = run_cli("atlas " + shell_quote(atlas) + " --no-cache -q -o " + shell_quote(dir / "out.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(has(r.err, "warning: " + atlas + ": frame 'b': trimmed sprite at 3,0 size 8x8 reaches outside sourceSize 10x8")) << r.err;
    EXPECT_TRUE(has(r.err, "warning: " + atlas + ": page " + (dir / "page.png").string() + " is 16x16, the atlas states 32x32")) << r.err;
    EXPECT_EQ(lines_starting(r.err, "warning: "), 2) << r.err;
    EXPECT_TRUE(fs::exists(dir / "out.json"));
    r = run_cli("atlas " + shell_quote(atlas) + " --no-cache -q --strict -o " + shell_quote(dir / "strict.json"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(has(r.err, "reaches outside sourceSize 10x8") && has(r.err, "(--strict)")) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "strict.json"));
    // A frame outside the decoded page stays an error, --strict or not.
    const std::string outside = write(dir / "outside.json",
                                      R"({"frames": {"a": {"frame": {"x": 12, "y": 0, "w": 8, "h": 8}}}, "meta": {"image": "page.png", "size": {"w": 32, "h": 32}}})");
    r = run_cli("atlas " + shell_quote(outside) + " --no-cache -q -o " + shell_quote(dir / "o.json"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(has(r.err, outside + ": frame 'a': texels 12,0 8x8 lie outside the 16x16 page")) << r.err;
}

TEST(RealFilesCli, CmykJpegAndAnimatedWebpWarnInInputOrderAndStrictRefuses) {
    const fs::path dir = test::scratch_dir("real_images");
    const std::uint8_t stored[4] = {255, 0, 255, 255};
    const std::string jpeg = write(dir / "a_cmyk.jpg", test::cmyk_jpeg_bytes(8, 8, stored));
    const std::string webp = write(dir / "b_anim.webp", test::animated_webp_bytes(8, 8, {0xff0000ff, 0x00ff00ff, 0x0000ffff}));
    io::write_png((dir / "c_plain.png").string(), test::ascii_image({"##", "#."}).view());
    // Warnings in input order for any thread count: the decodes run in parallel.
    std::string first;
    for (const char* threads : {"1", "3"}) {
        auto r = run_cli("analyze " + shell_quote(webp) + " " + shell_quote(dir / "c_plain.png") + " " + shell_quote(jpeg) +
                         " --no-cache -q --no-timing -j " + threads);
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(r.err, "warning: " + webp + ": animated WebP (3 frames): its first frame is used\n" + "warning: " + jpeg +
                             ": CMYK JPEG: converted to RGB as (1-C)(1-K) without its colour profile (colours may differ from a "
                             "colour-managed viewer's)\n")
            << r.err;
        if (first.empty()) first = r.out;
        EXPECT_EQ(r.out, first);
    }
    auto r = run_cli("analyze " + shell_quote(webp) + " --no-cache -q --strict");
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(has(r.err, webp + ": animated WebP (3 frames): its first frame is used (--strict)")) << r.err;
    r = run_cli("analyze " + shell_quote(jpeg) + " --no-cache -q --strict");
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(has(r.err, jpeg + ": CMYK JPEG") && has(r.err, "(--strict)")) << r.err;
    // Through a scene (optimize decodes its images in parallel too).
    const std::string scene = write(dir / "scene.json", R"({"images": [{"id": "w", "path": "b_anim.webp"}, {"id": "j", "path": "a_cmyk.jpg"}],
        "elements": [{"image": "w"}, {"image": "j", "transform": [1, 0, 0, 1, 4, 4]}]})");
    r = run_cli("optimize " + shell_quote(scene) + " --no-cache -q -j 2 -o " + shell_quote(dir / "m.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(lines_starting(r.err, "warning: "), 2) << r.err;
    EXPECT_LT(r.err.find("animated WebP"), r.err.find("CMYK JPEG")) << r.err;
    r = run_cli("optimize " + shell_quote(scene) + " --no-cache -q --strict -o " + shell_quote(dir / "s.json"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_TRUE(has(r.err, "animated WebP") && has(r.err, "(--strict)")) << r.err;
    EXPECT_FALSE(fs::exists(dir / "s.json"));
}
