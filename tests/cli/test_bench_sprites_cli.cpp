// bench --sprites N / --bunnymark N (issue 23): every frame, every mode
// (plain batching, meshes only, depth-culled) is measured and equals the
// overpaint of the same layers off texel edges; deterministic counts.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli/run_cli.h"

using depthcull::test::example;
using depthcull::test::run_cli;
using depthcull::test::shell_quote;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const char* kModes[] = {"plain batching", "meshes only", "depth-culled"};

// Every frame has every mode, with draws, and no pixel off a texel edge
// differs from overpaint.
void expect_frames(const json& scene, int frames) {
    ASSERT_EQ(scene["frames"].size(), std::size_t(frames)) << scene.dump();
    for (const json& f : scene["frames"])
        for (const char* mode : kModes) {
            ASSERT_TRUE(f.contains(mode)) << f.dump();
            EXPECT_GT(f[mode]["draw_calls"].get<int>(), 0) << mode;
            EXPECT_GT(f[mode]["fragments_shaded"].get<std::int64_t>(), 0) << mode;
            EXPECT_EQ(f[mode]["pixels_differ_off_texel_edges"], 0) << mode << ": " << f.dump();
        }
}

} // namespace

TEST(BenchSpritesCli, BunnymarkMeasuresEveryFrameInEveryMode) {
    auto r = run_cli("bench " + shell_quote(example("meadow.json")) + " --bunnymark 400 --frames 4 --json --no-cache");
    ASSERT_EQ(r.status, 0) << r.err;
    const json j = json::parse(r.out);
    ASSERT_EQ(j["scenes"].size(), 1u);
    const json& s = j["scenes"][0];
    EXPECT_EQ(s["sprites"], 400);
    EXPECT_EQ(s["bunnymark"], true);
    EXPECT_EQ(s["static_elements"], 0);
    expect_frames(s, 4);
    // The opaque pass rejects hidden fragments: the depth-culled frames shade fewer.
    std::int64_t plain = 0, culled = 0;
    for (const json& f : s["frames"]) plain += f["plain batching"]["fragments_shaded"].get<std::int64_t>(), culled += f["depth-culled"]["fragments_shaded"].get<std::int64_t>();
    EXPECT_LT(culled, plain);
    // The same seed gives the same counts.
    auto again = run_cli("bench " + shell_quote(example("meadow.json")) + " --bunnymark 400 --frames 4 --json --no-cache");
    ASSERT_EQ(again.status, 0) << again.err;
    const json k = json::parse(again.out);
    for (std::size_t f = 0; f < 4; ++f)
        for (const char* mode : kModes)
            for (const char* key : {"draw_calls", "triangles", "fragments_shaded", "pixels_differ"})
                EXPECT_EQ(k["scenes"][0]["frames"][f][mode][key], s["frames"][f][mode][key]) << mode << " " << key;
}

TEST(BenchSpritesCli, SpritesMoveInTheTiledGameLayer) {
    const std::string map = std::string(DEPTHCULL_SOURCE_DIR) + "/tests/data/tiled/objects.tmx";
    auto r = run_cli("bench " + shell_quote(map) + " --sprites 300 --frames 3 --json --no-cache");
    ASSERT_EQ(r.status, 0) << r.err;
    const json s = json::parse(r.out)["scenes"][0];
    EXPECT_EQ(s["scene_insertion_point"], true);
    EXPECT_EQ(s["insertion_element"], 2); // after the first object layer's two objects
    expect_frames(s, 3);
    // The table form names the three modes and the game layer.
    r = run_cli("bench " + shell_quote(map) + " --sprites 50 --frames 2 --no-cache");
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* mode : kModes) EXPECT_NE(r.out.find(mode), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("before static element 2 (the scene's first insertion point)"), std::string::npos) << r.out;
}

// --target: the moving sprites keep only opaque polygons that pay on the
// profile (fewer pictures with any), and the frames stay identical.
TEST(BenchSpritesCli, TargetKeepsOnlyOpaquePolygonsThatPay) {
    auto all = run_cli("bench " + shell_quote(example("meadow.json")) + " --bunnymark 100 --frames 2 --json --no-cache");
    auto paid = run_cli("bench " + shell_quote(example("meadow.json")) + " --bunnymark 100 --frames 2 --json --no-cache --target ipad1");
    ASSERT_EQ(all.status, 0) << all.err;
    ASSERT_EQ(paid.status, 0) << paid.err;
    const json a = json::parse(all.out), p = json::parse(paid.out);
    EXPECT_EQ(p["target"], "ipad1");
    EXPECT_LE(p["scenes"][0]["pictures_with_opaque"].get<int>(), a["scenes"][0]["pictures_with_opaque"].get<int>());
    EXPECT_EQ(p["scenes"][0]["pictures"], a["scenes"][0]["pictures"]);
    expect_frames(p["scenes"][0], 2);
}

TEST(BenchSpritesCli, SpritesAndBunnymarkTogetherIsAUsageError) {
    auto r = run_cli("bench " + shell_quote(example("meadow.json")) + " --sprites 5 --bunnymark 5");
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_NE(r.err.find("--sprites and --bunnymark"), std::string::npos) << r.err;
    r = run_cli("bench " + shell_quote(example("meadow.json")) + " --sprites 0");
    EXPECT_EQ(r.status, 2) << r.err;
}
