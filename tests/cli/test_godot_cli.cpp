// atlas --godot: one .tscn per frame with a Polygon2D. The text is checked
// exactly for a small frame; the scenes are loaded by Godot 3 itself
// (godot3-server, headless; skipped without it) and the arrays it reports
// must be our polygons: polygon = "vertices", uv = "verticesUV",
// polygons = "triangles" of the atlas JSON written in the same run.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli/run_cli.h"
#include "depthcull/io.h"

using namespace depthcull;
using io::AtlasFrame;
using depthcull::test::run_cli;
namespace fs = std::filesystem;

TEST(GodotExport, SceneTextIsExact) {
    AtlasFrame frame;
    frame.name = "ui/arrow.png";
    frame.frame = {10, 20, 4, 3};
    frame.sprite_source = {1, 2, 4, 3};
    frame.source_w = 6;
    frame.source_h = 5;
    std::vector<Polygon> boundary = {{{10, 20}, {14, 20}, {14, 23}, {10, 23}}};
    std::string text = io::godot_polygon_scene(frame, boundary, "../sheet.png");
    std::vector<std::uint32_t> t = triangulate_polygon(boundary[0]);
    ASSERT_EQ(t.size(), 6u);
    std::string tri = "PoolIntArray( " + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) +
                      " ), PoolIntArray( " + std::to_string(t[3]) + ", " + std::to_string(t[4]) + ", " + std::to_string(t[5]) + " )";
    EXPECT_EQ(text, "[gd_scene load_steps=2 format=2]\n\n"
                    "[ext_resource path=\"../sheet.png\" type=\"Texture\" id=1]\n\n"
                    "[node name=\"ui_arrow_png\" type=\"Polygon2D\"]\n"
                    "texture = ExtResource( 1 )\n"
                    "polygon = PoolVector2Array( 1, 2, 5, 2, 5, 5, 1, 5 )\n"
                    "uv = PoolVector2Array( 10, 20, 14, 20, 14, 23, 10, 23 )\n"
                    "polygons = [ " + tri + " ]\n");
    // A fully transparent frame draws nothing.
    EXPECT_NE(io::godot_polygon_scene(frame, {}, "s.png").find("polygon = PoolVector2Array( )\n"), std::string::npos);
}

TEST(GodotExport, Godot3LoadsOurPolygons) {
    if (std::system("command -v godot3-server >/dev/null 2>&1") != 0) GTEST_SKIP() << "godot3-server not installed (Debian package godot3-server)";
    fs::path project = fs::temp_directory_path() / ("dc_godot_" + std::to_string(::getpid()));
    fs::remove_all(project);
    fs::create_directories(project);
    std::ofstream(project / "project.godot") << "config_version=4\n\n[application]\nconfig/name=\"depthcull test\"\n";
    const std::string src = DEPTHCULL_SOURCE_DIR;
    for (const char* f : {"hash-0.json", "hash-0.png"}) fs::copy_file(src + "/tests/data/atlas/packed/" + f, project / f);
    fs::copy_file(src + "/tests/data/godot/check.gd", project / "check.gd");
    auto r = run_cli("atlas '" + (project / "hash-0.json").string() + "' -o '" + (project / "out.json").string() + "' --godot '" +
                     (project / "frames").string() + "' --no-cache -q");
    ASSERT_EQ(r.status, 0) << r.err;
    // Godot's own stderr is noisy at exit (leak reports): only its result line counts.
    std::string command = "cd '" + project.string() + "' && HOME='" + project.string() + "' timeout 120 godot3-server --path . -s check.gd 2>/dev/null";
    FILE* p = ::popen(command.c_str(), "r");
    ASSERT_TRUE(p);
    std::string out;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    ::pclose(p);
    auto at = out.find("GODOT_RESULT ");
    ASSERT_NE(at, std::string::npos) << out;
    auto godot = nlohmann::json::parse(out.substr(at + 13, out.find('\n', at) - at - 13));
    auto atlas = nlohmann::json::parse(std::ifstream(project / "out.json"));
    ASSERT_EQ(godot.size(), atlas["frames"].size());
    for (auto& [name, f] : atlas["frames"].items()) {
        std::string scene = fs::path(name).replace_extension().string() + ".tscn";
        ASSERT_TRUE(godot.contains(scene)) << scene;
        const auto& g = godot[scene];
        EXPECT_EQ(g["class"], "Polygon2D");
        EXPECT_EQ(g["texture"], "res://hash-0.png") << scene;
        EXPECT_EQ(g["polygon"], f["vertices"]) << scene;
        EXPECT_EQ(g["uv"], f["verticesUV"]) << scene;
        EXPECT_EQ(g["polygons"], f["triangles"]) << scene;
    }
    fs::remove_all(project);
}
