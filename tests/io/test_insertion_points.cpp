// Insertion points for moving sprites (issue 23) in files: where scenes
// say they are (Tiled object layers and layers named by LoadOptions::
// insert_at, the scene JSON's "insertion_points" key, element indices),
// and the reserved depth ranges in both meshes forms, so a game loading
// our output can draw sprites between the layers. Round trips, one-line
// errors naming the place, and files without points as they were.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "test_scene_json_helpers.h"
#include "tiled_expect.h"

namespace depthcull::test {
namespace {

struct Dir : SceneDir {
    Dir() : SceneDir("insertion_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())) {}
};

// Twelve overlapping elements; points before element 4 and 9.
std::string twelve_elements(const Dir& dir, const std::string& extra = R"(, "insertion_points": [9, 4])") {
    dir.standard_art();
    std::string elements;
    for (int i = 0; i < 12; ++i) {
        if (i) elements += ",";
        elements += R"({"image": ")" + std::string(i % 3 ? "blob" : "tiles") + R"(", "rect": [0, 0, 8, 8], "transform": [1, 0, 0, 1, )" +
                    std::to_string((i * 7) % 30) + ", " + std::to_string((i * 5) % 20) + "]}";
    }
    return dir.write("scene.json", R"({"viewport": {"x": 0, "y": 0, "width": 40, "height": 30},
        "images": [{"id": "blob", "path": "art/blob.png"}, {"id": "tiles", "path": "art/tiles.png"}], "elements": [)" +
                                       elements + "]" + extra + "}");
}

struct Reconstructed {
    pipeline::PreparedScene p;
    SceneMeshes meshes;
};

Reconstructed reconstructed(const std::string& path, std::int64_t levels = 50) {
    Reconstructed r{pipeline::prepare_scene(path, {}), {}};
    ReconstructOptions options;
    for (std::size_t at : r.p.scene.insertion_points) options.insertion_points.push_back({at, levels});
    EXPECT_EQ(reconstruct_scene(r.p.scene, r.p.analysis, options, &r.meshes), ReconstructStatus::ok);
    return r;
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const depthcull::Error& e) {
        return e.what();
    }
    return "no error";
}

template <class T>
std::string patched(std::string bytes, std::size_t at, T value) {
    std::memcpy(bytes.data() + at, &value, sizeof value);
    return bytes;
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

// ---- Scenes

TEST(InsertionPoints, SceneJsonKeyReadsSortedAndWritesBack) {
    Dir dir;
    const Scene s = io::read_scene(twelve_elements(dir));
    EXPECT_EQ(s.insertion_points, (std::vector<std::size_t>{4, 9}));
    const std::string text = io::scene_to_json_text(s, dir.path("again.json"));
    EXPECT_NE(text.find("\"insertion_points\""), std::string::npos) << text;
    EXPECT_EQ(io::read_scene(dir.write("again.json", text)).insertion_points, s.insertion_points);
    // Without points: no key (files as before).
    Scene none = s;
    none.insertion_points.clear();
    EXPECT_EQ(io::scene_to_json_text(none, dir.path("none.json")).find("insertion_points"), std::string::npos);
}

TEST(InsertionPoints, SceneJsonKeyErrorsNameTheFile) {
    Dir dir;
    for (const char* bad : {R"(, "insertion_points": [13])", R"(, "insertion_points": [-1])", R"(, "insertion_points": ["a"])",
                            R"(, "insertion_points": 3)", R"(, "insertion_points": [1.5])"}) {
        const std::string path = twelve_elements(dir, bad);
        const std::string error = error_of([&] { io::read_scene(path); });
        EXPECT_NE(error.find("scene.json: "), std::string::npos) << bad << ": " << error;
        EXPECT_NE(error.find("insertion"), std::string::npos) << bad << ": " << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    }
    // 12 (on top) is fine.
    EXPECT_EQ(io::read_scene(twelve_elements(dir, R"(, "insertion_points": [12])")).insertion_points, std::vector<std::size_t>{12});
}

TEST(InsertionPoints, InsertAtNamesElementIndicesOfScenes) {
    Dir dir;
    const std::string path = twelve_elements(dir);
    io::LoadOptions options;
    options.insert_at = {"0", "9", "12"};
    EXPECT_EQ(io::read_scene(path, options).insertion_points, (std::vector<std::size_t>{0, 4, 9, 12}));
    for (const char* bad : {"13", "x", "-1", "", "4x"}) {
        options.insert_at = {bad};
        const std::string error = error_of([&] { io::read_scene(path, options); });
        EXPECT_NE(error.find("scene.json: --insert-at '" + std::string(bad) + "': not an element index in 0..12"), std::string::npos) << error;
    }
}

std::string map_xml(const std::string& body, const std::string& map_attrs = "") {
    return "<?xml version=\"1.0\"?><map version=\"1.10\" orientation=\"orthogonal\" width=\"3\" height=\"2\" tilewidth=\"4\" tileheight=\"4\" " +
           map_attrs + "><tileset firstgid=\"1\" name=\"tiles\" tilewidth=\"4\" tileheight=\"4\" spacing=\"1\" margin=\"1\"><image source=\"" +
           data("tiles.png") + "\"/></tileset>" + body + "</map>";
}

const char* kLayers = "<layer name=\"ground\" width=\"3\" height=\"2\"><data encoding=\"csv\">1,2,0,0,0,0</data></layer>"
                      "<objectgroup name=\"game\"><object gid=\"1\" x=\"0\" y=\"8\" width=\"4\" height=\"4\"/></objectgroup>"
                      "<layer name=\"deco\" width=\"3\" height=\"2\"><data encoding=\"csv\">0,0,3,4,0,0</data></layer>"
                      "<layer name=\"hidden\" visible=\"0\" width=\"3\" height=\"2\"><data encoding=\"csv\">1,1,1,1,1,1</data></layer>"
                      "<layer name=\"roof\" width=\"3\" height=\"2\"><data encoding=\"csv\">0,0,0,0,1,1</data></layer>";

TEST(InsertionPoints, TiledObjectLayersAndNamedLayers) {
    Dir dir;
    const std::string path = dir.write("map.tmx", map_xml(kLayers));
    // ground 0-1, game 2, deco 3-4, roof 5-6.
    Scene s = io::read_scene(path);
    ASSERT_EQ(s.elements.size(), 7u);
    EXPECT_EQ(s.insertion_points, std::vector<std::size_t>{3});
    io::LoadOptions options;
    options.insert_at = {"deco", "ground", "hidden", "game"};
    s = io::read_scene(path, options);
    EXPECT_EQ(s.insertion_points, (std::vector<std::size_t>{2, 3, 5}));
    options.insert_at = {"nope"};
    EXPECT_EQ(error_of([&] { io::read_scene(path, options); }), path + ": --insert-at 'nope': the map has no layer of that name");
}

// A background colour is an element before every layer: the points move
// with the elements (before, they stayed put and the sprites went one
// element too low).
TEST(InsertionPoints, TiledBackgroundColourKeepsPointsAfterTheirLayer) {
    Dir dir;
    const Scene s = io::read_scene(dir.write("bg.tmx", map_xml(kLayers, "backgroundcolor=\"#102030\"")));
    ASSERT_EQ(s.elements.size(), 8u);
    EXPECT_TRUE(s.images[std::size_t(s.elements[0].image)].has_fill);
    EXPECT_EQ(s.insertion_points, std::vector<std::size_t>{4});
}

// ---- Meshes files

TEST(InsertionPoints, MeshesRoundTripInBothForms) {
    Dir dir;
    const Reconstructed r = reconstructed(twelve_elements(dir));
    ASSERT_EQ(r.meshes.insertion_points.size(), 2u);
    std::filesystem::create_directories(dir.path("out"));
    const std::string jpath = dir.path("out/m.json"), bpath = dir.path("out/m.bin");
    io::write_meshes_json(jpath, io::meshes_document(r.p.scene, r.meshes));
    io::write_meshes_binary(bpath, io::meshes_document(r.p.scene, r.meshes));
    const io::MeshesDocument j = io::read_meshes(jpath), b = io::read_meshes(bpath);
    for (const io::MeshesDocument* m : {&j, &b}) {
        EXPECT_EQ(m->meshes.insertion_points, r.meshes.insertion_points);
        EXPECT_EQ(m->meshes.depth_denominator, r.meshes.depth_denominator);
        EXPECT_EQ(m->meshes.stats, r.meshes.stats);
        ASSERT_EQ(m->meshes.draws.size(), r.meshes.draws.size());
    }
    EXPECT_EQ(io::meshes_to_json(j, jpath), io::read_file(jpath));
    EXPECT_EQ(io::meshes_to_binary(b, bpath), io::read_file(bpath));
    EXPECT_EQ(io::meshes_to_binary(j, bpath), io::read_file(bpath));
    EXPECT_EQ(io::meshes_to_json(b, jpath), io::read_file(jpath));
    std::uint32_t flags = 0;
    std::memcpy(&flags, io::read_file(bpath).data() + 12, 4);
    EXPECT_EQ(flags & 16u, 16u);
}

TEST(InsertionPoints, MeshesWithoutPointsAreAsBefore) {
    Dir dir;
    const Reconstructed r = reconstructed(twelve_elements(dir, ""));
    EXPECT_TRUE(r.meshes.insertion_points.empty());
    EXPECT_EQ(io::meshes_to_json(io::meshes_document(r.p.scene, r.meshes), "").find("insertion_points"), std::string::npos);
    const std::string bytes = io::meshes_to_binary(io::meshes_document(r.p.scene, r.meshes), "");
    std::uint32_t flags = 0;
    std::memcpy(&flags, bytes.data() + 12, 4);
    EXPECT_EQ(flags & 16u, 0u);
    EXPECT_TRUE(io::meshes_from_binary(bytes, "m.bin").meshes.insertion_points.empty());
}

TEST(InsertionPoints, JsonErrorsNameThePath) {
    Dir dir;
    const Reconstructed r = reconstructed(twelve_elements(dir));
    const std::string text = io::meshes_to_json(io::meshes_document(r.p.scene, r.meshes), "");
    const InsertionPoint& p0 = r.meshes.insertion_points[0];
    const InsertionPoint& p1 = r.meshes.insertion_points[1];
    ASSERT_NO_THROW(io::meshes_from_json(text, "m.json"));
    auto field = [&](const InsertionPoint& p) {
        return "{\"element\": " + std::to_string(p.element) + ", \"levels\": " + std::to_string(p.levels) + ", \"first_level\": " +
               std::to_string(p.first_level) + ", \"blend_draw\": " + std::to_string(p.blend_draw) + "}";
    };
    auto with = [&](const InsertionPoint& p, const std::string& replacement) { return replaced(text, field(p), replacement); };
    const std::string levels = std::to_string(r.meshes.stats.depth_levels);
    const std::string draws = std::to_string(r.meshes.draws.size());
    const std::pair<std::string, std::string> cases[] = {
        {with(p1, "{\"element\": 13, \"levels\": 50, \"first_level\": " + std::to_string(p1.first_level) + ", \"blend_draw\": 0}"),
         "m.json: insertion_points[1].element: element 13 is past the scene's 12 elements"},
        {with(p1, "{\"element\": 3, \"levels\": 50, \"first_level\": " + std::to_string(p1.first_level) + ", \"blend_draw\": 0}"),
         "m.json: insertion_points[1].element: element 3 is before the previous point's"},
        {with(p0, "{\"element\": 4, \"levels\": -1, \"first_level\": 0, \"blend_draw\": 0}"), "m.json: insertion_points[0].levels: must be an integer"},
        {with(p1, "{\"element\": 9, \"levels\": 50, \"first_level\": " + levels + ", \"blend_draw\": " + std::to_string(p1.blend_draw) + "}"),
         "m.json: insertion_points[1].first_level: levels " + levels + " + 50 are not inside the " + levels + " depth levels"},
        {with(p1, "{\"element\": 9, \"levels\": 50, \"first_level\": " + std::to_string(p0.first_level + 1) + ", \"blend_draw\": " +
                      std::to_string(p1.blend_draw) + "}"),
         "m.json: insertion_points[1].first_level: first_level " + std::to_string(p0.first_level + 1) + " overlaps the previous point's levels"},
        {with(p1, "{\"element\": 9, \"levels\": 50, \"first_level\": " + std::to_string(p1.first_level) + ", \"blend_draw\": " + draws + "1}"),
         "m.json: insertion_points[1].blend_draw: blend_draw " + draws + "1 is past the " + draws + " draws"},
        {with(p0, "{\"element\": 4, \"levels\": 50, \"first_level\": " + std::to_string(p0.first_level) + ", \"blend_draw\": 0}"),
         "m.json: insertion_points[0].blend_draw: blend_draw 0 is not in the blend pass"},
        {with(p0, "{\"element\": 4, \"levels\": 51, \"first_level\": " + std::to_string(p0.first_level) + ", \"blend_draw\": " +
                      std::to_string(p0.blend_draw) + "}"),
         "m.json: insertion_points: draw "},
        {replaced(text, "\"insertion_points\": [", "\"insertion_points\": [3, "), "m.json: insertion_points[0]: must be an object"},
        {replaced(text, "\"insertion_points\": [", "\"insertion_points\": [{}, "), "m.json: insertion_points[0]: missing \"element\""},
    };
    for (const auto& [t, expected] : cases) {
        const std::string& text = t; // clang 14 cannot capture a structured binding
        const std::string error = error_of([&] { io::meshes_from_json(text, "m.json"); });
        EXPECT_EQ(error.substr(0, expected.size()), expected) << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    }
    // Meshes without depth values cannot have points.
    SceneMeshes flat = overpaint_meshes(r.p.scene);
    flat.insertion_points = {{4, 1, 0, std::uint32_t(flat.draws.size())}};
    const std::string error = error_of([&] { io::meshes_from_json(io::meshes_to_json(io::MeshesDocument{.images = r.p.scene.images, .meshes = flat}, ""), "m.json"); });
    EXPECT_NE(error.find("insertion points need depth values"), std::string::npos) << error;
}

TEST(InsertionPoints, BinaryErrorsNameTheByte) {
    Dir dir;
    const Reconstructed r = reconstructed(twelve_elements(dir));
    const std::string b = io::meshes_to_binary(io::meshes_document(r.p.scene, r.meshes), "");
    ASSERT_NO_THROW(io::meshes_from_binary(b, "m.bin"));
    // The section: count, then two points of 32 bytes.
    const std::size_t count = b.size() - 4 - 2 * 32, p0 = count + 4, p1 = p0 + 32;
    const std::pair<std::string, std::string> cases[] = {
        {patched(b, count, std::uint32_t(0)), "m.bin: byte " + std::to_string(count) + ": flags bit 4 (insertion points) is set but the insertion point count is 0"},
        {patched(b, count, std::uint32_t(1 << 20)), "m.bin: byte " + std::to_string(count) + ": more than 65536 insertion points"},
        {patched(b, count, std::uint32_t(3)), "m.bin: byte " + std::to_string(count) + ": 3 insertion points do not fit in the 64 bytes left"},
        {patched(b, p1, std::uint64_t(13)), "m.bin: byte " + std::to_string(p1) + ": insertion point 1: element 13 is past the scene's 12 elements"},
        {patched(b, p1, std::uint64_t(~0ull)), "m.bin: byte " + std::to_string(p1) + ": insertion point element"},
        {patched(b, p0 + 8, std::int64_t(-2)), "m.bin: byte " + std::to_string(p0 + 8) + ": insertion point 0: levels -2 is outside"},
        {patched(b, p1 + 16, std::int64_t(r.meshes.insertion_points[0].first_level)),
         "m.bin: byte " + std::to_string(p1 + 16) + ": insertion point 1: first_level"},
        {patched(b, p1 + 24, std::uint32_t(1000)), "m.bin: byte " + std::to_string(p1 + 24) + ": insertion point 1: blend_draw 1000 is past"},
        {patched(b, p1 + 28, std::uint32_t(1)), "m.bin: byte " + std::to_string(p1 + 28) + ": insertion point reserved field is not 0"},
        {patched(b, p0 + 8, std::int64_t(r.meshes.insertion_points[0].levels + 1)), "m.bin: byte " + std::to_string(count) + ": draw "},
        {b + "x", "m.bin: byte " + std::to_string(b.size()) + ": 1 bytes after the insertion points"},
    };
    for (const auto& [bytes, expected] : cases) {
        const std::string& data = bytes; // clang 14 cannot capture a structured binding
        const std::string error = error_of([&] { io::meshes_from_binary(data, "m.bin"); });
        EXPECT_EQ(error.substr(0, expected.size()), expected) << error;
    }
    for (std::size_t n = count; n < b.size(); ++n) EXPECT_NE(error_of([&] { io::meshes_from_binary(b.substr(0, n), "m.bin"); }), "no error") << n;
    // An old reader's view: the flag is unknown to it, and a file with the
    // flag clear but the section present has bytes left over.
    const std::string error = error_of([&] { io::meshes_from_binary(patched(b, 12, std::uint32_t(1)), "m.bin"); });
    EXPECT_NE(error.find("bytes after the last draw"), std::string::npos) << error;
}

} // namespace
} // namespace depthcull::test
