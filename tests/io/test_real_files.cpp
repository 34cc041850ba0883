// Issue 21, points 1, 7a and 8a: files engines load must load (atlases
// whose stated page size differs from the image, Aseprite trims past
// sourceSize, CMYK JPEGs, animated WebPs), with a warning line naming the
// file and what was assumed, an error with --strict; colour keys on the
// file's own PNG samples; JSON errors that quote no file content. Every
// file is made here.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "depthcull/io.h"
#include "depthcull/target.h"
#include "testing/ascii_image.h"
#include "testing/image_files.h"

using namespace depthcull;
namespace fs = std::filesystem;

namespace {

fs::path scratch() {
    fs::path dir = fs::temp_directory_path() /
                   ("dc_real_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string write(const fs::path& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
    return path.string();
}

template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const depthcull::Error& e) {
        return e.what();
    }
    return "(no error)";
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// Loads `scene` collecting warning lines (strict: the error instead).
Scene load_warned(const std::string& scene, std::vector<std::string>* lines, bool strict = false) {
    io::LoadOptions options;
    options.warning = [lines](const std::string& line) { lines->push_back(line); };
    options.strict = strict;
    return io::read_scene(scene, options);
}

} // namespace

TEST(RealFiles, PngGammaChunkKeepsTheFilesSamplesSoAColourKeyMatches) {
    // gAMA 1.0 (linear): libpng's simplified API turned 0x80 into 0xbc, and
    // trans=808080 keyed nothing. WebGL, stb_image and Tiled use 0x80.
    const fs::path dir = scratch();
    const std::string path = write(dir / "linear.png", test::png_bytes(2, 1, {0x80, 0x80, 0x80, 0x10, 0x20, 0x30}, false, 1.0));
    const Image image = io::read_image(path);
    ASSERT_EQ(image.width, 2);
    EXPECT_EQ(image.rgba, (std::vector<std::uint8_t>{0x80, 0x80, 0x80, 255, 0x10, 0x20, 0x30, 255}));
    SceneImage keyed;
    keyed.path = path;
    keyed.has_trans = true;
    keyed.trans = 0x808080;
    const Image key = io::read_scene_image(keyed);
    EXPECT_EQ(key.rgba[3], 0);   // keyed
    EXPECT_EQ(key.rgba[7], 255); // not
}

TEST(RealFiles, SixteenBitPngRoundsToEightBitsWithoutALinearConversion) {
    // 0x1234 of 0xffff is 18.1 of 255; read as linear light and encoded as
    // sRGB (the simplified API's way) it became 76.
    const fs::path dir = scratch();
    const std::vector<std::uint8_t> samples{0x12, 0x34, 0x80, 0x80, 0xff, 0xff};
    const Image image = io::read_image(write(dir / "deep.png", test::png_bytes(1, 1, samples, true)));
    auto round8 = [](unsigned v) { return std::uint8_t((v * 255 + 32767) / 65535); };
    EXPECT_EQ(image.rgba, (std::vector<std::uint8_t>{round8(0x1234), round8(0x8080), 255, 255}));
}

TEST(RealFiles, CmykJpegConvertsToRgbWithAWarning) {
    // Inverted inks as Photoshop stores them: no cyan, full magenta, no
    // yellow, no black: (1-C)(1-K) = 1, (1-M)(1-K) = 0, (1-Y)(1-K) = 1.
    const fs::path dir = scratch();
    const std::uint8_t stored[4] = {255, 0, 255, 255};
    const std::string path = write(dir / "cmyk.jpg", test::cmyk_jpeg_bytes(16, 16, stored));
    std::vector<std::string> warnings;
    const Image image = io::read_image(path, &warnings);
    ASSERT_EQ(image.width, 16);
    for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
        EXPECT_NEAR(image.rgba[i], 255, 3);
        EXPECT_NEAR(image.rgba[i + 1], 0, 3);
        EXPECT_NEAR(image.rgba[i + 2], 255, 3);
        EXPECT_EQ(image.rgba[i + 3], 255);
    }
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0].rfind(path + ": CMYK JPEG: converted to RGB", 0), 0u) << warnings[0];
}

TEST(RealFiles, AnimatedWebpGivesItsFirstFrameWithAWarning) {
    const fs::path dir = scratch();
    const std::string path = write(dir / "anim.webp", test::animated_webp_bytes(4, 3, {0xff0000ff, 0x0000ffff}));
    std::vector<std::string> warnings;
    const Image image = io::read_image(path, &warnings);
    ASSERT_EQ(image.width, 4);
    ASSERT_EQ(image.height, 3);
    for (std::size_t i = 0; i < image.rgba.size(); i += 4)
        EXPECT_EQ(std::vector<std::uint8_t>(image.rgba.begin() + long(i), image.rgba.begin() + long(i) + 4),
                  (std::vector<std::uint8_t>{255, 0, 0, 255}));
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], path + ": animated WebP (2 frames): its first frame is used");
}

TEST(RealFiles, AtlasFramesAreTexelsOfTheDecodedPageNotOfMetaSize) {
    // A page re-saved at 32x32 while meta.size still says 64x64: engines
    // load it (neither PixiJS nor Phaser reads meta.size), so do we, with a
    // warning; a frame outside the decoded page is refused even though the
    // stated size would hold it; --strict refuses the difference.
    const fs::path dir = scratch();
    io::write_png((dir / "page.png").string(), test::ascii_image(std::vector<std::string>(32, std::string(32, '#'))).view());
    auto atlas = [&](const std::string& name, int x) {
        return write(dir / name, R"({"frames": {"a": {"frame": {"x": )" + std::to_string(x) +
                                     R"(, "y": 0, "w": 8, "h": 8}}}, "meta": {"image": "page.png", "size": {"w": 64, "h": 64}}})");
    };
    atlas("ok.json", 24);
    atlas("out.json", 40);
    auto scene = [&](const std::string& name, const std::string& atlas_name) {
        return write(dir / name, R"({"images": [{"id": "s", "atlas": ")" + atlas_name + R"("}], "elements": [{"image": "s", "frame": "a"}]})");
    };
    std::vector<std::string> lines;
    const Scene s = load_warned(scene("ok_scene.json", "ok.json"), &lines);
    ASSERT_EQ(s.elements.size(), 1u);
    EXPECT_EQ(s.elements[0].rect, (Rect{24, 0, 8, 8}));
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_TRUE(has(lines[0], "ok.json: page ")) << lines[0];
    EXPECT_TRUE(has(lines[0], "page.png is 32x32, the atlas states 64x64; frames read as texels of the image")) << lines[0];
    const std::string strict = error_of([&] { load_warned(scene("strict_scene.json", "ok.json"), &lines, true); });
    EXPECT_TRUE(has(strict, "the atlas states 64x64") && has(strict, "(--strict)")) << strict;
    const std::string out = error_of([&] { load_warned(scene("out_scene.json", "out.json"), &lines); });
    EXPECT_TRUE(has(out, "out.json: frame 'a': texels 40,0 8x8 lie outside the 32x32 page")) << out;
}

TEST(RealFiles, MetaScaleIsWarnedAndFramesStayAtTexelSize) {
    const fs::path dir = scratch();
    io::write_png((dir / "page.png").string(), test::ascii_image(std::vector<std::string>(8, std::string(8, '#'))).view());
    write(dir / "half.json", R"({"frames": {"a": {"frame": {"x": 0, "y": 0, "w": 8, "h": 8}}}, "meta": {"image": "page.png", "scale": "0.5"}})");
    EXPECT_EQ(io::read_atlas((dir / "half.json").string()).scale, 0.5);
    const std::string scene = write(dir / "scene.json", R"({"images": [{"id": "s", "atlas": "half.json"}], "elements": [{"image": "s", "frame": "a"}]})");
    std::vector<std::string> lines;
    const Scene s = load_warned(scene, &lines);
    EXPECT_EQ(s.elements[0].transform, (std::array<double, 6>{1, 0, 0, 1, 0, 0}));
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_TRUE(has(lines[0], "half.json: meta.scale 0.5: frames placed at their texel size")) << lines[0];
}

TEST(RealFiles, AsepriteTrimOneTexelPastSourceSizeLoadsWithAWarning) {
    // Aseprite: frame at 27,31 of a 90x80 sprite, 64x36 texels: x reaches 91.
    const fs::path dir = scratch();
    const std::string json = write(dir / "ase.json", R"({"frames": {"walk 0": {"frame": {"x": 0, "y": 0, "w": 64, "h": 36}, "trimmed": true,
        "spriteSourceSize": {"x": 27, "y": 31, "w": 64, "h": 36}, "sourceSize": {"w": 90, "h": 80}}}, "meta": {"image": "ase.png"}})");
    const io::Atlas a = io::read_atlas(json);
    ASSERT_EQ(a.frames.size(), 1u);
    EXPECT_EQ(a.frames[0].sprite_source, (Rect{27, 31, 64, 36}));
    ASSERT_EQ(a.warnings.size(), 1u);
    EXPECT_EQ(a.warnings[0].rfind(json + ": frame 'walk 0': trimmed sprite at 27,31 size 64x36 reaches outside sourceSize 90x80", 0), 0u)
        << a.warnings[0];
    // The same frame in a cocos2d-x plist (format 2).
    const std::string plist = write(dir / "ase.plist", R"(<?xml version="1.0" encoding="UTF-8"?>
<plist version="1.0"><dict>
<key>frames</key><dict><key>walk 0</key><dict>
<key>frame</key><string>{{0,0},{64,36}}</string><key>offset</key><string>{0,0}</string><key>rotated</key><false/>
<key>sourceColorRect</key><string>{{27,31},{64,36}}</string><key>sourceSize</key><string>{90,80}</string>
</dict></dict>
<key>metadata</key><dict><key>format</key><integer>2</integer><key>textureFileName</key><string>ase.png</string><key>size</key><string>{64,36}</string></dict>
</dict></plist>)");
    const io::Atlas p = io::read_atlas(plist);
    ASSERT_EQ(p.frames.size(), 1u);
    EXPECT_EQ(p.frames[0].sprite_source, (Rect{27, 31, 64, 36}));
    ASSERT_EQ(p.warnings.size(), 1u);
    EXPECT_TRUE(has(p.warnings[0], plist + ": frame 'walk 0': trimmed sprite at 27,31 size 64x36 reaches outside its source size 90x80"))
        << p.warnings[0];
}

TEST(RealFiles, InvalidJsonIsReportedWithoutItsContent) {
    // nlohmann's text quoted the bytes last read ("last read: 'SECRET...'"),
    // and "number overflow parsing '...'" the number: one form for every
    // reader, naming the place and never the content.
    const fs::path dir = scratch();
    const std::string secret = "SECRETtoken";
    const std::string tileset = write(dir / "t.tsj", "{\"name\": " + secret + "}");
    const std::string map = write(dir / "m.tmx", R"(<?xml version="1.0"?><map orientation="orthogonal" width="1" height="1" tilewidth="4" tileheight="4">
<tileset firstgid="1" source="t.tsj"/><layer name="l" width="1" height="1"><data encoding="csv">1</data></layer></map>)");
    struct Case {
        std::string file, error;
    };
    std::vector<Case> cases;
    cases.push_back({tileset, error_of([&] { io::read_scene(map); })});
    const std::string tmj = write(dir / "m.tmj", "{\"layers\": [\n  \"" + secret + "\", " + secret + "]}");
    cases.push_back({tmj, error_of([&] { io::read_scene(tmj); })});
    const std::string scene = write(dir / "s.json", "{\"images\": " + secret + "}");
    cases.push_back({scene, error_of([&] { io::read_scene(scene); })});
    const std::string atlas = write(dir / "a.json", "{\"frames\": {\"" + secret + "\": 1e999}}");
    cases.push_back({atlas, error_of([&] { io::read_atlas(atlas); })});
    cases.push_back({"m.json", error_of([&] { io::meshes_from_json("{\"viewport\": " + secret, "m.json"); })});
    cases.push_back({"p.json", error_of([&] { pipeline::profile_from_json("[" + secret + "]", "p.json"); })});
    for (const Case& c : cases) {
        EXPECT_EQ(c.error.rfind(c.file + ": not valid JSON at line ", 0), 0u) << c.error;
        EXPECT_FALSE(has(c.error, "SECRET") || has(c.error, "last read") || has(c.error, "1e999")) << c.error;
        EXPECT_EQ(c.error.find('\n'), std::string::npos) << c.error;
    }
    EXPECT_TRUE(has(cases[1].error, "at line 2, column 18 (byte 30): syntax error while parsing value - invalid literal")) << cases[1].error;
    EXPECT_TRUE(has(cases[3].error, "at line 1, column 28 (byte 27): number out of the range of a double")) << cases[3].error;
}
