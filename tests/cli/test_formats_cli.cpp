// Issue 15 through the command line: sprite sheets cut by grid=, Tiled
// warnings and --strict, atlas outputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli/run_cli.h"
#include "depthcull/io.h"
#include "testing/ascii_image.h"

using namespace depthcull;
using depthcull::test::run_cli;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return depthcull::test::scratch_dir("cli_formats_" + name); }

} // namespace

TEST(GridCli, EveryCellItsOwnFrameAndEmptyCellsGiveNoPolygon) {
    fs::path dir = scratch("grid");
    // Margin 1, spacing 1, 3x2 cells: the middle one fully transparent, the
    // right one's texels touching the cell's right edge (not the next cell's).
    Image strip = test::ascii_image({"............",
                                     ".##.....#.#.",
                                     ".##......##.",
                                     "............"});
    io::write_png((dir / "strip.png").string(), strip.view());
    auto r = run_cli("analyze '" + (dir / "strip.png").string() + ":grid=3,2,1,1' --no-cache");
    ASSERT_EQ(r.status, 0) << r.err;
    auto images = nlohmann::json::parse(r.out)["images"];
    ASSERT_EQ(images.size(), 3u); // a 4th column would need 13 texels
    EXPECT_EQ(images[0]["rect"], nlohmann::json({1, 1, 3, 2}));
    EXPECT_EQ(images[1]["rect"], nlohmann::json({5, 1, 3, 2}));
    EXPECT_EQ(images[2]["rect"], nlohmann::json({9, 1, 3, 2}));
    for (int i = 0; i < 3; ++i) EXPECT_EQ(images[std::size_t(i)]["cell"], i);
    EXPECT_EQ(images[0]["stats"]["nontransparent_texels"], 4);
    EXPECT_EQ(images[1]["boundary"].size(), 0u); // fully transparent: no polygon
    EXPECT_EQ(images[1]["opaque"].size(), 0u);
    EXPECT_EQ(images[2]["stats"]["nontransparent_texels"], 3);
    for (const auto& poly : images[2]["boundary"])
        for (const auto& v : poly) {
            EXPECT_GE(v[0].get<double>(), 9.0);
            EXPECT_LE(v[0].get<double>(), 12.0);
        }
    // Without margin and spacing: 4x2 cells of the 12x4 image.
    r = run_cli("analyze '" + (dir / "strip.png").string() + ":grid=4,2' --no-cache");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["images"].size(), 6u);
    // A grid no cell fits: one line naming it.
    r = run_cli("analyze '" + (dir / "strip.png").string() + ":grid=13,2' --no-cache");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("strip.png:grid=13,2: the 12x4 image holds no 13x2 grid cell"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
}

TEST(TiledCli, WarningsAndStrict) {
    fs::path dir = scratch("strict");
    std::string tiles = std::string(DEPTHCULL_SOURCE_DIR) + "/tests/data/tiled/tiles.png";
    std::ofstream(dir / "anim.tmx") << "<map orientation=\"orthogonal\" width=\"1\" height=\"1\" tilewidth=\"4\" tileheight=\"4\">"
                                       "<tileset firstgid=\"1\" name=\"t\" tilewidth=\"4\" tileheight=\"4\" margin=\"1\" spacing=\"1\"><image source=\"" +
                                           tiles + "\"/><tile id=\"0\"><animation><frame tileid=\"1\" duration=\"9\"/></animation></tile></tileset>"
                                                   "<objectgroup name=\"o\"><object id=\"1\" x=\"0\" y=\"0\"><text>x</text></object></objectgroup>"
                                                   "<layer name=\"g\" width=\"1\" height=\"1\"><data encoding=\"csv\">1</data></layer></map>";
    std::string map = (dir / "anim.tmx").string();
    auto r = run_cli("import '" + map + "' -o '" + (dir / "s.json").string() + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("warning: " + map + ": object layer 'o': text objects are not drawn\n"), std::string::npos) << r.err;
    r = run_cli("import '" + map + "' --strict -o '" + (dir / "s.json").string() + "'");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(map + ": object layer 'o': text objects are not drawn (--strict)"), std::string::npos) << r.err;
}

TEST(AtlasCli, PlistOutput) {
    fs::path dir = scratch("plist");
    std::string packed = std::string(DEPTHCULL_SOURCE_DIR) + "/tests/data/atlas/packed/";
    auto r = run_cli("atlas '" + packed + "hash-0.json' -o '" + (dir / "out.plist").string() + "' --no-cache");
    ASSERT_EQ(r.status, 0) << r.err;
    io::Atlas back = io::read_atlas((dir / "out.plist").string());
    EXPECT_EQ(back.plist_format, 3);
    EXPECT_EQ(back.frames.size(), 6u);
    r = run_cli("atlas '" + packed + "phaser3-multi.json' -o '" + (dir / "multi.plist").string() + "' --no-cache");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("a cocos2d-x plist holds one page; this multipack has 2"), std::string::npos) << r.err;
}
