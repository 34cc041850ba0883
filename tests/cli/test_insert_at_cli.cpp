// optimize --insert-at / --insertion-levels (issue 23): the meshes files
// carry reserved depth ranges where moving sprites go, from a Tiled map's
// object layers and named layers or a scene's element indices; a point
// naming nothing is a one-line error that writes no file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli/run_cli.h"
#include "depthcull/io.h"

using depthcull::test::example;
using depthcull::test::run_cli;
using depthcull::test::scratch_dir;
using depthcull::test::shell_quote;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string tiled(const std::string& name) { return std::string(DEPTHCULL_SOURCE_DIR) + "/tests/data/tiled/" + name; }

} // namespace

TEST(InsertAtCli, SceneElementIndicesBecomeInsertionPointsInBothFiles) {
    const fs::path dir = scratch_dir("insert_at_scene");
    auto r = run_cli("optimize " + shell_quote(example("meadow.json")) + " --no-cache --no-timing --insert-at 3 --insert-at 40 -o " +
                     shell_quote(dir / "m.json") + " --binary " + shell_quote(dir / "m.bin"));
    ASSERT_EQ(r.status, 0) << r.err;
    const json j = json::parse(std::ifstream(dir / "m.json"));
    ASSERT_TRUE(j.contains("insertion_points")) << r.err;
    ASSERT_EQ(j["insertion_points"].size(), 2u);
    EXPECT_EQ(j["insertion_points"][0]["element"], 3);
    EXPECT_EQ(j["insertion_points"][0]["levels"], 1024);
    EXPECT_EQ(j["insertion_points"][1]["element"], 40);
    const auto a = depthcull::io::read_meshes((dir / "m.json").string()), b = depthcull::io::read_meshes((dir / "m.bin").string());
    EXPECT_EQ(a.meshes.insertion_points, b.meshes.insertion_points);
    // --insertion-levels sets the range; without either option, no points.
    r = run_cli("optimize " + shell_quote(example("meadow.json")) + " --no-cache --insert-at 3 --insertion-levels 7 -o " + shell_quote(dir / "m7.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(json::parse(std::ifstream(dir / "m7.json"))["insertion_points"][0]["levels"], 7);
    r = run_cli("optimize " + shell_quote(example("meadow.json")) + " --no-cache -o " + shell_quote(dir / "none.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_FALSE(json::parse(std::ifstream(dir / "none.json")).contains("insertion_points"));
    // Levels but no point anywhere: said, not silently dropped.
    r = run_cli("optimize " + shell_quote(example("meadow.json")) + " --no-cache --insertion-levels 10 -o " + shell_quote(dir / "none.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("--insertion-levels: the scene has no insertion point"), std::string::npos) << r.err;
    EXPECT_FALSE(json::parse(std::ifstream(dir / "none.json")).contains("insertion_points"));
}

TEST(InsertAtCli, TiledObjectLayersAndNamedLayers) {
    const fs::path dir = scratch_dir("insert_at_tiled");
    // Object layers alone, with --insertion-levels: after 'sorted' (2
    // elements) and 'indexed' (2 more).
    auto r = run_cli("optimize " + shell_quote(tiled("objects.tmx")) + " --no-cache --insertion-levels 100 -o " + shell_quote(dir / "m.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    json j = json::parse(std::ifstream(dir / "m.json"));
    ASSERT_EQ(j["insertion_points"].size(), 2u) << j["insertion_points"].dump();
    EXPECT_EQ(j["insertion_points"][0]["element"], 2);
    EXPECT_EQ(j["insertion_points"][1]["element"], 4);
    EXPECT_EQ(j["insertion_points"][1]["levels"], 100);
    // A named group: after its elements (the same place as 'sorted').
    r = run_cli("optimize " + shell_quote(tiled("objects.tmx")) + " --no-cache --insert-at g -o " + shell_quote(dir / "g.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(json::parse(std::ifstream(dir / "g.json"))["insertion_points"].size(), 2u);
}

TEST(InsertAtCli, PointsNamingNothingAreOneLineErrorsAndWriteNothing) {
    const fs::path dir = scratch_dir("insert_at_bad");
    const std::pair<std::string, std::string> cases[] = {
        {shell_quote(tiled("objects.tmx")) + " --insert-at nope", "--insert-at 'nope': the map has no layer of that name"},
        {shell_quote(example("meadow.json")) + " --insert-at 100000", "--insert-at '100000': not an element index in 0.."},
        {shell_quote(example("meadow.json")) + " --insert-at ground", "--insert-at 'ground': not an element index in 0.."},
    };
    for (const auto& [args, expected] : cases) {
        auto r = run_cli("optimize " + args + " --no-cache -o " + shell_quote(dir / "m.json"));
        EXPECT_EQ(r.status, 1) << args;
        EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(dir / "m.json"));
    }
    auto r = run_cli("optimize " + shell_quote(example("meadow.json")) + " --insertion-levels -1 -o " + shell_quote(dir / "m.json"));
    EXPECT_EQ(r.status, 2) << r.err;
    // More reserved levels than a 24-bit depth buffer resolves.
    r = run_cli("optimize " + shell_quote(example("meadow.json")) + " --no-cache --insert-at 1 --insert-at 2 --insertion-levels 2000000 -o " +
                shell_quote(dir / "m.json"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("2 insertion points x 2000000 levels (--insertion-levels) are more than the 2097151 depth levels"), std::string::npos) << r.err;
    r = run_cli("optimize " + shell_quote(example("meadow.json")) + " --no-cache --insert-at 1 --insertion-levels 2097151 -o " + shell_quote(dir / "m.json"));
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_NE(r.err.find("insertion points' levels too long for a 24-bit depth buffer"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "m.json"));
}
