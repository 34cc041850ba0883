// The asset-build commands end to end: optimize, import, atlas.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli/run_cli.h"

using depthcull::test::example;
using depthcull::test::run_cli;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

fs::path scratch(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / ("dc_pipe_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string shq(const fs::path& p) { return "'" + p.string() + "'"; }

int files_in(const fs::path& dir) {
    int n = 0;
    for (auto& e : fs::directory_iterator(dir)) (void)e, ++n;
    return n;
}

} // namespace

TEST(OptimizeCli, WritesMeshesWithTheDocumentedFields) {
    fs::path dir = scratch("optimize");
    auto r = run_cli("optimize " + shq(example("meadow.json")) + " --no-cache -o " + shq(dir / "m.json") + " --binary " +
                     shq(dir / "m.bin"));
    ASSERT_EQ(r.status, 0) << r.err;
    json j = json::parse(std::ifstream(dir / "m.json"));
    EXPECT_EQ(j["viewport"]["width"], 640);
    EXPECT_EQ(j["images"].size(), 10u);
    ASSERT_FALSE(j["draws"].empty());
    bool saw_opaque = false;
    for (const auto& d : j["draws"]) {
        EXPECT_EQ(d["vertices"].size() % 9, 0u);
        EXPECT_EQ(d["indices"].size() % 3, 0u);
        saw_opaque |= d["pass"] == "opaque";
        for (std::size_t v = 2; v < d["vertices"].size(); v += 9) {
            double z = d["vertices"][v];
            EXPECT_GE(z, 0.0);
            EXPECT_LE(z, 1.0);
        }
    }
    EXPECT_TRUE(saw_opaque);
    for (const char* key : {"elements", "draw_calls", "triangles", "depth_levels", "seconds"}) EXPECT_TRUE(j["stats"].contains(key)) << key;
    EXPECT_EQ(j["stats"]["elements"], 459);
    EXPECT_LT(j["stats"]["draw_calls"].get<int>(), 459 / 4); // batching: far fewer draws than elements
    EXPECT_GT(fs::file_size(dir / "m.bin"), 16u);
}

// --stats: overdraw before and after from the CPU analyzers (no GL), and
// the filter the meshes are made for in both forms; --filter wins over the
// scene's own.
TEST(OptimizeCli, StatsPrintOverdrawAndMeshesRecordTheFilter) {
    fs::path dir = scratch("optimize_stats");
    auto r = run_cli("optimize " + shq(example("meadow.json")) + " --no-cache --stats -o " + shq(dir / "m.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    for (const char* row : {"fragments rasterized", "fragments shaded", "overdraw", "ideal overdraw"})
        EXPECT_NE(r.out.find(row), std::string::npos) << row << "\n" << r.out;
    EXPECT_EQ(json::parse(std::ifstream(dir / "m.json"))["filter"], "nearest");
    r = run_cli("optimize " + shq(example("meadow.json")) + " --no-cache --filter linear -o " + shq(dir / "l.json") + " --binary " +
                shq(dir / "l.bin"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(json::parse(std::ifstream(dir / "l.json"))["filter"], "linear");
    std::ifstream bin(dir / "l.bin", std::ios::binary);
    char header[16] = {};
    bin.read(header, sizeof header);
    EXPECT_EQ(header[12] & 4, 4) << "binary flags bit 2: linear";
}

TEST(OptimizeCli, ByteIdenticalAcrossThreadCountsAndCacheRuns) {
    fs::path dir = scratch("determinism");
    std::string base = "optimize " + shq(example("meadow.json")) + " --no-timing --cache " + shq(dir / "cache");
    ASSERT_EQ(run_cli(base + " -j 1 -o " + shq(dir / "a.json") + " --binary " + shq(dir / "a.bin")).status, 0);
    ASSERT_EQ(run_cli(base + " -j 4 -o " + shq(dir / "b.json") + " --binary " + shq(dir / "b.bin")).status, 0); // from the cache
    ASSERT_EQ(run_cli("optimize " + shq(example("meadow.json")) + " --no-timing --no-cache -j 2 -o " + shq(dir / "c.json")).status, 0);
    auto bytes = [](const fs::path& p) { std::ifstream in(p, std::ios::binary); return std::string(std::istreambuf_iterator<char>(in), {}); };
    EXPECT_EQ(bytes(dir / "a.json"), bytes(dir / "b.json"));
    EXPECT_EQ(bytes(dir / "a.json"), bytes(dir / "c.json"));
    EXPECT_EQ(bytes(dir / "a.bin"), bytes(dir / "b.bin"));
    // With timing, stats.seconds is the reconstruction's wall time, measured
    // by the command (the library's values hold none): the only difference.
    ASSERT_EQ(run_cli("optimize " + shq(example("meadow.json")) + " --cache " + shq(dir / "cache") + " -o " + shq(dir / "t.json")).status, 0);
    json timed = json::parse(bytes(dir / "t.json")), untimed = json::parse(bytes(dir / "a.json"));
    EXPECT_TRUE(timed["stats"]["seconds"].is_number()); // its value is the machine's, not the test's
    EXPECT_EQ(untimed["stats"]["seconds"], 0);
    timed["stats"]["seconds"] = 0;
    EXPECT_EQ(timed, untimed);
}

TEST(OptimizeCli, BadSceneGivesOneLineErrorNamingTheElementAndWritesNothing) {
    fs::path dir = scratch("bad_scene");
    fs::copy(example("art"), dir / "art", fs::copy_options::recursive);
    std::ofstream(dir / "s.json") << R"({"viewport": {"width": 64, "height": 64},
        "images": [{"id": "rock", "path": "art/rock.png"}],
        "elements": [{"image": "rock"}, {"image": "rok"}]})";
    fs::path out = dir / "out.json";
    auto r = run_cli("optimize " + shq(dir / "s.json") + " --no-cache -o " + shq(out));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("s.json"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("1"), std::string::npos) << r.err; // element index
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(files_in(dir), 2); // art/ and s.json: no temporary left

    std::ofstream(dir / "nan.json") << R"({"viewport": {"width": 64, "height": 64},
        "images": [{"id": "rock", "path": "art/rock.png"}],
        "elements": [{"image": "rock", "transform": [1, 0, 0, 1, "x", 0]}]})";
    EXPECT_NE(run_cli("optimize " + shq(dir / "nan.json") + " --no-cache -o " + shq(out)).status, 0);
    std::ofstream(dir / "missing.json") << R"({"viewport": {"width": 64, "height": 64},
        "images": [{"id": "rock", "path": "art/nothere.png"}], "elements": [{"image": "rock"}]})";
    r = run_cli("optimize " + shq(dir / "missing.json") + " --no-cache -o " + shq(out));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("nothere.png"), std::string::npos) << r.err;
    EXPECT_NE(run_cli("optimize " + shq(dir / "truncated.json") + " --no-cache").status, 0);
    EXPECT_FALSE(fs::exists(out));
}

TEST(ImportCli, TiledMapBecomesASceneThatOptimizes) {
    fs::path dir = scratch("import");
    fs::path map = fs::path(DEPTHCULL_SOURCE_DIR) / "tests/data/tiled";
    fs::path tmx;
    for (auto& e : fs::directory_iterator(map))
        if (e.path().extension() == ".tmx" && (tmx.empty() || e.path() < tmx)) tmx = e.path();
    ASSERT_FALSE(tmx.empty());
    auto r = run_cli("import " + shq(tmx) + " -o " + shq(dir / "scene.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    json scene = json::parse(std::ifstream(dir / "scene.json"));
    EXPECT_FALSE(scene["elements"].empty());
    EXPECT_FALSE(scene["images"].empty());
    r = run_cli("optimize " + shq(dir / "scene.json") + " --no-cache -o " + shq(dir / "m.json"));
    EXPECT_EQ(r.status, 0) << r.err;
    // the map itself optimizes the same way
    r = run_cli("optimize " + shq(tmx) + " --no-cache --no-timing -o " + shq(dir / "direct.json"));
    EXPECT_EQ(r.status, 0) << r.err;
}

TEST(ImportCli, BrokenMapGivesOneLineError) {
    fs::path dir = scratch("import_bad");
    std::ofstream(dir / "bad.tmx") << R"(<?xml version="1.0"?><map orientation="orthogonal" width="2" height="1" tilewidth="8" tileheight="8">
        <layer name="ground" width="2" height="1"><data encoding="base64">!!!notbase64</data></layer></map>)";
    auto r = run_cli("import " + shq(dir / "bad.tmx") + " -o " + shq(dir / "s.json"));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("bad.tmx"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "s.json"));
}

TEST(AtlasCli, WritesTexturePackerPolygonFieldsKeepingTheRest) {
    fs::path dir = scratch("atlas");
    auto r = run_cli("atlas " + shq(example("atlas/sheet.json")) + " -o " + shq(dir / "out.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    json in = json::parse(std::ifstream(example("atlas/sheet.json")));
    json out = json::parse(std::ifstream(dir / "out.json"));
    EXPECT_EQ(out["meta"], in["meta"]);
    ASSERT_EQ(out["frames"].size(), in["frames"].size());
    for (auto& [name, frame] : out["frames"].items()) {
        EXPECT_EQ(frame["frame"], in["frames"][name]["frame"]) << name;
        ASSERT_TRUE(frame.contains("vertices")) << name;
        EXPECT_EQ(frame["vertices"].size(), frame["verticesUV"].size()) << name;
        EXPECT_FALSE(frame["triangles"].empty()) << name;
        for (const auto& t : frame["triangles"]) { // TexturePacker nests them: [[i, j, k], ...]
            ASSERT_EQ(t.size(), 3u) << name;
            for (const auto& i : t) EXPECT_LT(i.get<std::size_t>(), frame["vertices"].size()) << name;
        }
    }
}
