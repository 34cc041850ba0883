// The meshes readers: write -> read -> write is byte-identical and gives
// the same values, in both forms; bad files get one-line errors naming the
// place (JSON path or byte offset), limits are checked before allocating.
#include <charconv>
#include <cstring>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_scene_json_helpers.h"

namespace depthcull::test {
namespace {

struct Optimized {
    pipeline::PreparedScene prepared;
    SceneMeshes meshes;
    double seconds = 0.125; // the document's stats.seconds (exact in both forms)
    // What `depthcull optimize` writes for these meshes, timed.
    io::MeshesDocument document() const {
        io::MeshesDocument d = io::meshes_document(prepared.scene, meshes);
        d.seconds = seconds;
        return d;
    }
};

Optimized optimized_scene(const SceneDir& dir) {
    dir.standard_art();
    std::string elements;
    for (int i = 0; i < 12; ++i) {
        if (i) elements += ",";
        elements += R"({"image": ")" + std::string(i % 3 ? "blob" : "tiles") + R"(", "rect": [0, 0, 8, 8], "transform": [1, 0, 0, 1, )" +
                    std::to_string((i * 7) % 30) + ", " + std::to_string((i * 5) % 20) + "]" +
                    (i % 4 == 1 ? R"(, "blend": "add", "color": [1, 0.5, 0.25, 0.75])" : "") + "}";
    }
    std::string path = dir.write("scene.json", R"({"viewport": {"x": -3, "y": 2, "width": 40, "height": 30},
        "images": [{"id": "blob", "path": "art/blob.png"}, {"id": "tiles", "path": "art/tiles.png"}], "elements": [)" + elements + "]}");
    Optimized o{pipeline::prepare_scene(path, {}), {}};
    EXPECT_EQ(reconstruct_scene(o.prepared.scene, o.prepared.analysis, {}, &o.meshes), ReconstructStatus::ok);
    return o;
}

void expect_same_meshes(const SceneMeshes& a, const SceneMeshes& b) {
    EXPECT_EQ(a.viewport.x, b.viewport.x);
    EXPECT_EQ(a.viewport.y, b.viewport.y);
    EXPECT_EQ(a.viewport.width, b.viewport.width);
    EXPECT_EQ(a.viewport.height, b.viewport.height);
    EXPECT_EQ(a.depth_test, b.depth_test);
    EXPECT_EQ(a.filter, b.filter);
    EXPECT_EQ(a.depth_denominator, b.depth_denominator);
    ASSERT_EQ(a.draws.size(), b.draws.size());
    for (std::size_t i = 0; i < a.draws.size(); ++i) {
        EXPECT_EQ(a.draws[i].image, b.draws[i].image) << i;
        EXPECT_EQ(a.draws[i].pass, b.draws[i].pass) << i;
        EXPECT_EQ(a.draws[i].blend, b.draws[i].blend) << i;
        EXPECT_EQ(a.draws[i].vertices, b.draws[i].vertices) << i;
        EXPECT_EQ(a.draws[i].indices, b.draws[i].indices) << i;
    }
    EXPECT_EQ(a.stats.elements, b.stats.elements);
    EXPECT_EQ(a.stats.draw_calls, b.stats.draw_calls);
    EXPECT_EQ(a.stats.triangles, b.stats.triangles);
    EXPECT_EQ(a.stats.depth_levels, b.stats.depth_levels);
    EXPECT_EQ(a.stats.depth_bits, b.stats.depth_bits);
    EXPECT_EQ(a.stats.graph_edges, b.stats.graph_edges);
}

void expect_same_images(const std::vector<SceneImage>& a, const std::vector<SceneImage>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].id, b[i].id);
        EXPECT_EQ(std::filesystem::path(a[i].path).lexically_normal(), std::filesystem::path(b[i].path).lexically_normal());
        EXPECT_EQ(a[i].width, b[i].width);
        EXPECT_EQ(a[i].height, b[i].height);
        EXPECT_EQ(a[i].has_trans, b[i].has_trans);
        EXPECT_EQ(a[i].trans, b[i].trans);
    }
}

TEST(MeshReaders, JsonRoundTripIsByteIdenticalWithEqualValues) {
    SceneDir dir("mesh_read_json");
    Optimized o = optimized_scene(dir);
    std::filesystem::create_directories(dir.path("out"));
    const std::string path = dir.path("out/meshes.json");
    io::write_meshes_json(path, o.document());
    io::MeshesDocument loaded = io::read_meshes(path);
    expect_same_meshes(o.meshes, loaded.meshes);
    expect_same_images(o.prepared.scene.images, loaded.images);
    EXPECT_EQ(loaded.seconds, o.seconds);
    EXPECT_EQ(io::meshes_to_json(loaded, path), io::read_file(path));
    for (const Draw& d : loaded.meshes.draws) EXPECT_TRUE(d.element_spans.empty());
}

TEST(MeshReaders, BinaryRoundTripIsByteIdenticalWithEqualValues) {
    SceneDir dir("mesh_read_bin");
    Optimized o = optimized_scene(dir);
    std::filesystem::create_directories(dir.path("out"));
    const std::string path = dir.path("out/meshes.bin");
    io::write_meshes_binary(path, o.document());
    io::MeshesDocument loaded = io::read_meshes(path);
    expect_same_meshes(o.meshes, loaded.meshes);
    expect_same_images(o.prepared.scene.images, loaded.images);
    EXPECT_EQ(loaded.seconds, o.seconds);
    EXPECT_EQ(io::meshes_to_binary(loaded, path), io::read_file(path));
}

TEST(MeshReaders, ReadMeshesTellsTheFormsApartAndTheyAgree) {
    SceneDir dir("mesh_read_any");
    Optimized o = optimized_scene(dir);
    io::write_meshes_json(dir.path("m.json"), o.document());
    io::write_meshes_binary(dir.path("m.bin"), o.document());
    io::MeshesDocument j = io::read_meshes(dir.path("m.json")), b = io::read_meshes(dir.path("m.bin"));
    expect_same_meshes(j.meshes, b.meshes);
    expect_same_images(j.images, b.images);
    EXPECT_EQ(j.seconds, b.seconds);
    // Converting one form into the other gives what the writer gives.
    EXPECT_EQ(io::meshes_to_binary(j, dir.path("m.bin")), io::read_file(dir.path("m.bin")));
    // Seconds 0 writes what a document made without a time writes.
    j.seconds = 0;
    EXPECT_EQ(io::meshes_to_binary(j, dir.path("m.bin")), io::meshes_to_binary(io::meshes_document(o.prepared.scene, o.meshes), dir.path("m.bin")));
}

TEST(MeshReaders, FromMemoryKeepsPathsAsWritten) {
    SceneDir dir("mesh_read_mem");
    Optimized o = optimized_scene(dir);
    const std::string text = io::meshes_to_json(o.document(), dir.path("sub/m.json"));
    io::MeshesDocument m = io::meshes_from_json(text, "memory");
    EXPECT_EQ(m.images[0].path, "../art/blob.png");
    EXPECT_EQ(io::meshes_to_json(m, ""), text);
    io::MeshesDocument based = io::meshes_from_json(text, "memory", "/assets/sub");
    EXPECT_EQ(based.images[0].path, "/assets/art/blob.png");
    const std::string bytes = io::meshes_to_binary(o.document(), dir.path("sub/m.bin"));
    EXPECT_EQ(io::meshes_to_binary(io::meshes_from_binary(bytes, "memory"), ""), bytes);
}

void expect_same_animations(const std::vector<Animation>& a, const std::vector<Animation>& b) {
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i].frames.size(), b[i].frames.size()) << i;
        for (std::size_t k = 0; k < a[i].frames.size(); ++k) {
            EXPECT_EQ(a[i].frames[k].image, b[i].frames[k].image) << i << " " << k;
            EXPECT_EQ(a[i].frames[k].rect, b[i].frames[k].rect) << i << " " << k;
            EXPECT_EQ(a[i].frames[k].duration_ms, b[i].frames[k].duration_ms) << i << " " << k;
        }
    }
}

// An animated scene (two frames of tiles.png, every third element
// animated), reconstructed with the element spans the "animated" runs need.
Optimized animated_scene(const SceneDir& dir) {
    dir.standard_art();
    std::string elements;
    for (int i = 0; i < 9; ++i) {
        if (i) elements += ",";
        elements += R"({"image": ")" + std::string(i % 3 ? "blob" : "tiles") + R"(", "rect": [0, 0, 8, 4], "transform": [1, 0, 0, 1, )" +
                    std::to_string((i * 7) % 30) + ", " + std::to_string((i * 5) % 20) + "]" + (i % 3 ? "" : R"(, "animation": 0)") + "}";
    }
    std::string path = dir.write("scene.json", R"({"viewport": {"x": 0, "y": 0, "width": 40, "height": 30},
        "images": [{"id": "blob", "path": "art/blob.png"}, {"id": "tiles", "path": "art/tiles.png"}],
        "animations": [{"frames": [{"image": "tiles", "rect": [0, 0, 8, 4], "duration": 100}, {"image": "tiles", "rect": [8, 0, 8, 4], "duration": 250}]}],
        "elements": [)" + elements + "]}");
    Optimized o{pipeline::prepare_scene(path, {}), {}};
    ReconstructOptions options;
    options.element_spans = true;
    EXPECT_EQ(reconstruct_scene(o.prepared.scene, o.prepared.analysis, options, &o.meshes), ReconstructStatus::ok);
    return o;
}

// Animations travel in both forms (binary: flags bit 3 and a section after
// the draws) and read back as the same values; converting one form into
// the other gives what the writer gives.
TEST(MeshReaders, AnimationsRoundTripInBothForms) {
    SceneDir dir("mesh_read_anim");
    Optimized o = animated_scene(dir);
    ASSERT_EQ(o.prepared.scene.animations.size(), 1u);
    const io::MeshesDocument document = o.document();
    const std::vector<io::AnimatedRun>& runs = document.animated;
    ASSERT_FALSE(runs.empty());
    std::filesystem::create_directories(dir.path("out"));
    const std::string jpath = dir.path("out/m.json"), bpath = dir.path("out/m.bin");
    io::write_meshes_json(jpath, document);
    io::write_meshes_binary(bpath, document);
    const io::MeshesDocument j = io::read_meshes(jpath), b = io::read_meshes(bpath);
    for (const io::MeshesDocument* m : {&j, &b}) {
        expect_same_meshes(o.meshes, m->meshes);
        expect_same_images(o.prepared.scene.images, m->images);
        expect_same_animations(m->animations, o.prepared.scene.animations);
        EXPECT_EQ(m->animated, runs);
    }
    EXPECT_EQ(j.animations[0].frames[1].rect, (Rect{8, 0, 8, 4}));
    EXPECT_EQ(j.animations[0].frames[1].duration_ms, 250);
    EXPECT_EQ(io::meshes_to_json(j, jpath), io::read_file(jpath));
    EXPECT_EQ(io::meshes_to_binary(b, bpath), io::read_file(bpath));
    EXPECT_EQ(io::meshes_to_binary(j, bpath), io::read_file(bpath));
    EXPECT_EQ(io::meshes_to_json(b, jpath), io::read_file(jpath));
    std::uint32_t flags = 0;
    std::memcpy(&flags, io::read_file(bpath).data() + 12, 4);
    EXPECT_EQ(flags & 8u, 8u);
    // Unanimated scenes: no section, no flag (files as before).
    Optimized plain = optimized_scene(dir);
    EXPECT_TRUE(plain.document().animated.empty());
    std::memcpy(&flags, io::meshes_to_binary(plain.document(), "").data() + 12, 4);
    EXPECT_EQ(flags & 8u, 0u);
    EXPECT_TRUE(io::meshes_from_binary(io::meshes_to_binary(plain.document(), ""), "m.bin").animations.empty());
}

// One document, three writers per form: a document read back from a file
// writes that file's bytes again, whichever writer (bytes, streamed
// pieces, atomic file) and whichever form it was read from, animations
// and stats.seconds included.
TEST(MeshReaders, DocumentReadFromAFileWritesTheSameBytes) {
    SceneDir dir("mesh_read_same");
    Optimized o = animated_scene(dir);
    std::filesystem::create_directories(dir.path("out"));
    const std::string jpath = dir.path("out/m.json"), bpath = dir.path("out/m.bin");
    io::write_meshes_json(jpath, o.document());
    io::write_meshes_binary(bpath, o.document());
    const std::string json = io::read_file(jpath), binary = io::read_file(bpath);
    ASSERT_NE(json.find("\"seconds\": 0.125}"), std::string::npos);
    ASSERT_NE(json.find("\"animated\""), std::string::npos);
    for (const std::string& from : {jpath, bpath}) {
        const io::MeshesDocument read = io::read_meshes(from);
        EXPECT_EQ(read.seconds, 0.125) << from;
        EXPECT_EQ(io::meshes_to_json(read, jpath), json) << from;
        EXPECT_EQ(io::meshes_to_binary(read, bpath), binary) << from;
        std::string streamed_json, streamed_binary;
        io::stream_meshes_json([&](std::string_view piece) { streamed_json += piece; }, read, jpath);
        io::stream_meshes_binary([&](std::string_view piece) { streamed_binary += piece; }, read, bpath);
        EXPECT_EQ(streamed_json, json) << from;
        EXPECT_EQ(streamed_binary, binary) << from;
        // Written again in the same directory: the same bytes (paths are
        // relative to the output's directory).
        io::write_meshes_json(dir.path("out/again.json"), read);
        io::write_meshes_binary(dir.path("out/again.bin"), read);
        EXPECT_EQ(io::read_file(dir.path("out/again.json")), json) << from;
        EXPECT_EQ(io::read_file(dir.path("out/again.bin")), binary) << from;
    }
}

std::string replaced(std::string s, const std::string& from, const std::string& to); // below

// stats.seconds stays in both forms: what a writer given no time writes is
// 0, and files that hold a time (`depthcull optimize` without --no-timing,
// and every file written before timings left the writers' parameters)
// still read, report it, and write it back as they were.
TEST(MeshReaders, OldFilesWithSecondsStillRead) {
    SceneDir dir("mesh_read_seconds");
    Optimized o = optimized_scene(dir);
    const io::MeshesDocument untimed = io::meshes_document(o.prepared.scene, o.meshes);
    EXPECT_EQ(untimed.seconds, 0);
    const std::string json = io::meshes_to_json(untimed, ""), binary = io::meshes_to_binary(untimed, "");
    ASSERT_NE(json.find("\"seconds\": 0}"), std::string::npos);
    double zero = -1;
    std::memcpy(&zero, binary.data() + 96, 8); // header: stats.seconds at bytes 96..103
    EXPECT_EQ(zero, 0.0);

    const std::string old_json = replaced(json, "\"seconds\": 0}", "\"seconds\": 3.75}");
    std::string old_binary = binary;
    const double seconds = 3.75;
    std::memcpy(old_binary.data() + 96, &seconds, 8);
    for (const std::string& old : {old_json, old_binary}) {
        const bool is_binary = io::is_binary_meshes(old);
        io::MeshesDocument read = is_binary ? io::meshes_from_binary(old, "old.bin") : io::meshes_from_json(old, "old.json");
        EXPECT_EQ(read.seconds, 3.75) << is_binary;
        expect_same_meshes(o.meshes, read.meshes);
        EXPECT_EQ(is_binary ? io::meshes_to_binary(read, "") : io::meshes_to_json(read, ""), old) << is_binary;
        read.seconds = 0;
        EXPECT_EQ(is_binary ? io::meshes_to_binary(read, "") : io::meshes_to_json(read, ""), is_binary ? binary : json) << is_binary;
    }
    // A JSON file without the field reads as not measured.
    EXPECT_EQ(io::meshes_from_json(replaced(json, ", \"seconds\": 0}", "}"), "old.json").seconds, 0);
}

// A colour key (Tiled's trans) is part of the image: both forms carry it,
// and files without keys are what they were before keys existed.
// The filter the meshes are made for travels in both forms: JSON "filter",
// binary flags bit 2 (clear for nearest, so those files are as before).
TEST(MeshReaders, FilterRoundTripsInBothForms) {
    SceneDir dir("mesh_read_filter");
    Optimized o = optimized_scene(dir);
    EXPECT_EQ(o.meshes.filter, Filter::nearest);
    std::uint32_t flags = 0;
    std::memcpy(&flags, io::meshes_to_binary(o.document(), "").data() + 12, 4);
    EXPECT_EQ(flags & 4u, 0u);
    EXPECT_NE(io::meshes_to_json(o.document(), "").find("\"filter\": \"nearest\""), std::string::npos);
    o.meshes.filter = Filter::linear;
    const std::string text = io::meshes_to_json(o.document(), "");
    EXPECT_NE(text.find("\"filter\": \"linear\""), std::string::npos);
    expect_same_meshes(o.meshes, io::meshes_from_json(text, "memory").meshes);
    const std::string bytes = io::meshes_to_binary(o.document(), "");
    std::memcpy(&flags, bytes.data() + 12, 4);
    EXPECT_EQ(flags & 4u, 4u);
    expect_same_meshes(o.meshes, io::meshes_from_binary(bytes, "memory").meshes);
    // Files written before the field: nearest.
    std::string old = text;
    old.erase(old.find(",\n \"filter\": \"linear\""), std::string(",\n \"filter\": \"linear\"").size());
    EXPECT_EQ(io::meshes_from_json(old, "memory").meshes.filter, Filter::nearest);
}

TEST(MeshReaders, ColourKeysRoundTripInBothForms) {
    SceneDir dir("mesh_read_keys");
    Optimized o = optimized_scene(dir);
    const std::string plain = io::meshes_to_binary(o.document(), "");
    std::uint32_t flags = 0;
    std::memcpy(&flags, plain.data() + 12, 4);
    EXPECT_EQ(flags & 2u, 0u);
    io::MeshesDocument document = o.document();
    std::vector<SceneImage>& keyed = document.images;
    keyed[0].has_trans = true;
    keyed[0].trans = 0xff00ff;
    const std::string text = io::meshes_to_json(document, "");
    EXPECT_NE(text.find("\"trans\": \"ff00ff\""), std::string::npos);
    // Written for stdout: paths relative to the working directory (when it
    // shares a directory with the images; absolute otherwise), so they are
    // read back against it, wherever the tests run.
    const std::string cwd = std::filesystem::current_path().string();
    expect_same_images(keyed, io::meshes_from_json(text, "memory", cwd).images);
    const std::string bytes = io::meshes_to_binary(document, "");
    expect_same_images(keyed, io::meshes_from_binary(bytes, "memory", cwd).images);
    EXPECT_EQ(io::meshes_to_binary(io::meshes_from_binary(bytes, "memory"), ""), bytes);
    std::string bad = text;
    bad.replace(bad.find("ff00ff"), 6, "ff00fg");
    try {
        io::meshes_from_json(bad, "bad.json");
        ADD_FAILURE() << "a bad colour key was read";
    } catch (const depthcull::Error& e) {
        EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
    }
}

// The JSON reader parses doubles and rounds them to float once; the
// writer's shortest float text must survive that for every float.
TEST(MeshReaders, ShortestFloatTextReadsBackThroughDouble) {
    std::mt19937 rng(13);
    for (int i = 0; i < 200000; ++i) {
        std::uint32_t bits = rng();
        float f;
        std::memcpy(&f, &bits, 4);
        if (!std::isfinite(f)) continue;
        char buf[32];
        auto r = std::to_chars(buf, buf + sizeof buf, f);
        const double d = nlohmann::json::parse(std::string(buf, r.ptr)).get<double>();
        ASSERT_EQ(float(d), f) << std::string(buf, r.ptr);
    }
}

// ---- Bad files

const char* kSmallJson = R"({"viewport": {"x": 0, "y": 0, "width": 8, "height": 8}, "depth_test": true,
 "images": [{"id": "a", "path": "a.png", "width": 4, "height": 4}],
 "draws": [{"image": "a", "pass": "blend", "blend": "alpha",
   "vertices": [0,0,0.5,0,0,1,1,1,1, 4,0,0.5,1,0,1,1,1,1, 0,4,0.5,0,1,1,1,1,1],
   "indices": [0,1,2]}],
 "stats": {"elements": 1, "draw_calls": 1, "triangles": 1, "depth_levels": 64, "depth_bits": 10, "graph_edges": 0, "seconds": 0}})";

std::string json_error(const std::string& text) {
    try {
        io::meshes_from_json(text, "m.json");
    } catch (const depthcull::Error& e) {
        return e.what();
    }
    return "no error";
}

std::string replaced(std::string s, const std::string& from, const std::string& to) {
    auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
}

TEST(MeshReaders, JsonErrorsNameThePath) {
    EXPECT_NO_THROW(io::meshes_from_json(kSmallJson, "m.json"));
    const std::string s = kSmallJson;
    const std::pair<std::string, std::string> cases[] = {
        {replaced(s, "[0,1,2]", "[0,1,3]"), "m.json: draws[0].indices[2]: must be an integer in 0..2"},
        {replaced(s, "[0,1,2]", "[0,1]"), "m.json: draws[0].indices: has 2 indices, not a multiple of 3"},
        {replaced(s, "[0,1,2]", "[0,1,-2]"), "m.json: draws[0].indices[2]:"},
        {replaced(s, "[0,0,0.5,", "[0,0,1.5,"), "m.json: draws[0].vertices[2]: is a depth (z) outside [0, 1]"},
        {replaced(s, "[0,0,0.5,", "[1e39,0,0.5,"), "m.json: draws[0].vertices[0]: is outside the range of a float"},
        {replaced(s, "[0,0,0.5,", "[\"x\",0,0.5,"), "m.json: draws[0].vertices[0]: must be a number"},
        {replaced(s, "[0,0,0.5,", "[0,0.5,"), "m.json: draws[0].vertices: has 26 numbers, not 9 per vertex"},
        {replaced(s, "\"pass\": \"blend\"", "\"pass\": \"front\""), "m.json: draws[0].pass: unknown pass \"front\""},
        {replaced(s, "\"blend\": \"alpha\"", "\"blend\": \"screen\""), "m.json: draws[0].blend: unknown blend \"screen\""},
        {replaced(s, "\"image\": \"a\"", "\"image\": \"b\""), "m.json: draws[0].image: unknown image id \"b\""},
        {replaced(s, "\"width\": 4", "\"width\": 99999"), "m.json: images[0].width: must be an integer in 0..16384"},
        {replaced(s, "\"depth_test\": true", "\"depth_test\": 1"), "m.json: depth_test: must be true or false"},
        {replaced(s, "\"depth_test\": true", "\"depth_test\": true, \"filter\": \"cubic\""), "m.json: filter: must be \"nearest\" or \"linear\""},
        {replaced(s, "\"viewport\"", "\"view\""), "m.json: top level: missing \"viewport\""},
        {replaced(s, "\"seconds\": 0", "\"seconds\": -1"), "m.json: stats.seconds: must not be negative"},
        {replaced(s, "\"triangles\": 1", "\"triangles\": 1.5"), "m.json: stats.triangles: must be an integer"},
        {"[1, 2]", "m.json: top level: expected a JSON object"},
        {"{\"viewport\": ", "m.json: not valid JSON at line 1, column 14 (byte 13): "},
    };
    for (const auto& [text, expected] : cases) {
        const std::string error = json_error(text);
        EXPECT_EQ(error.substr(0, expected.size()), expected) << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    }
}

std::string binary_error(const std::string& bytes) {
    try {
        io::meshes_from_binary(bytes, "m.bin");
    } catch (const depthcull::Error& e) {
        return e.what();
    }
    return "no error";
}

template <class T>
std::string patched(std::string bytes, std::size_t at, T v) {
    std::memcpy(bytes.data() + at, &v, sizeof v);
    return bytes;
}

TEST(MeshReaders, BinaryErrorsNameTheByte) {
    const io::MeshesDocument small = io::meshes_from_json(kSmallJson, "m.json");
    const std::string b = io::meshes_to_binary(small, "");
    ASSERT_NO_THROW(io::meshes_from_binary(b, "m.bin"));
    // Header 104 bytes; image "a"/"a.png": 4+1+4+5 = 14, padded to 16, sizes at 120; draw header at 128, vertices at 144.
    ASSERT_EQ(b.size(), 264u);
    const std::size_t counts = 40, draw = 128, vertices = 144, indices = vertices + 27 * 4;
    const std::pair<std::string, std::string> cases[] = {
        {"DCMESH", "m.bin: byte 0: not a depthcull binary meshes file"},
        {patched(b, 8, std::uint32_t(2)), "m.bin: byte 8: format version 2 is not supported"},
        {patched(b, 12, std::uint32_t(33)), "m.bin: byte 12: unknown flags 33"},
        {patched(b, 12, std::uint32_t(9)), "m.bin: byte 264: the file ends inside the animation count"},
        {patched(b, 16, std::numeric_limits<double>::quiet_NaN()), "m.bin: byte 16: viewport x is not a finite number"},
        {patched(b, counts, std::uint32_t(1 << 16)), "m.bin: byte 40: 65536 images and 1 draws do not fit in the"},
        {patched(b, counts, std::uint32_t(1 << 20)), "m.bin: byte 40: more than 65536 images"},
        {patched(b, counts + 4, std::uint32_t(1 << 24)), "m.bin: byte 40: 1 images and 16777216 draws do not fit"},
        {patched(b, counts + 4, std::uint32_t(0xffffffff)), "m.bin: byte 44: more than 16777216 draws"},
        {patched(b, 48, std::int64_t(-1)), "m.bin: byte 48: a negative stats count"},
        {patched(b, 119, char(1)), "m.bin: byte 119: an image entry padding is not zero"},
        {patched(b, 120, std::int32_t(-4)), "m.bin: byte 120: image width -4 is outside 0..16384"},
        {patched(b, draw, std::uint32_t(1)), "m.bin: byte 128: draw names image 1 of 1"},
        {patched(b, draw + 4, std::uint8_t(2)), "m.bin: byte 132: unknown pass 2"},
        {patched(b, draw + 5, std::uint8_t(4)), "m.bin: byte 133: unknown blend 4"},
        {patched(b, draw + 6, std::uint16_t(1)), "m.bin: byte 134: reserved field is not 0"},
        {patched(b, draw + 8, std::uint32_t(0xffffffff)), "m.bin: byte 136: more than 33554432 vertices"},
        {patched(b, draw + 8, std::uint32_t(1000)), "m.bin: byte 136: 1000 vertices and 3 indices do not fit in the 120 bytes left"},
        {patched(b, draw + 12, std::uint32_t(4)), "m.bin: byte 140: index count 4 is not a multiple of 3"},
        {patched(b, vertices + 4 * 11, std::numeric_limits<float>::infinity()), "m.bin: byte 188: vertex 1 value 2 is not a finite number"},
        {patched(b, vertices + 4 * 2, 2.0f), "m.bin: byte 152: vertex 0 value 2 is a depth (z) outside [0, 1]"},
        {patched(b, indices + 8, std::uint32_t(3)), "m.bin: byte 260: index 3 is not below the draw's vertex count 3"},
        {b + "x", "m.bin: byte 264: 1 bytes after the last draw"},
    };
    for (const auto& [bytes, expected] : cases) {
        const std::string error = binary_error(bytes);
        EXPECT_EQ(error.substr(0, expected.size()), expected) << error;
    }
    // Every truncation is an error naming where the file ends, never a crash.
    for (std::size_t n = 0; n < b.size(); ++n) EXPECT_NE(binary_error(b.substr(0, n)), "no error") << n;
}

const char* kSmallAnimations = R"(, "animations": [{"frames": [{"image": 0, "rect": [0, 0, 2, 2], "duration": 100}, {"image": 0, "rect": [2, 0, 2, 2], "duration": 50}]}],
 "animated": [{"draw": 0, "first_vertex": 1, "vertex_count": 2, "animation": 0}]})";

std::string small_animated_json() {
    std::string s = kSmallJson;
    return s.substr(0, s.size() - 1) + kSmallAnimations;
}

TEST(MeshReaders, AnimationErrorsNameThePlace) {
    const std::string text = small_animated_json();
    const io::MeshesDocument small = io::meshes_from_json(text, "m.json");
    ASSERT_EQ(small.animated.size(), 1u);
    const std::string b = io::meshes_to_binary(small, "");
    ASSERT_NO_THROW(io::meshes_from_binary(b, "m.bin"));
    // The 264 bytes of the unanimated file, then: count at 264, frame count
    // at 268, frames at 272 and 296 (24 bytes each), draw 0's run count at
    // 320, its run at 324.
    ASSERT_EQ(b.size(), 336u);
    const std::pair<std::string, std::string> cases[] = {
        {patched(b, 264, std::uint32_t(0)), "m.bin: byte 264: flags bit 3 (animations) is set but the animation count is 0"},
        {patched(b, 264, std::uint32_t(1 << 21)), "m.bin: byte 264: more than 1048576 animations"},
        {patched(b, 264, std::uint32_t(3)), "m.bin: byte 264: 3 animations and the runs of 1 draws do not fit in the 68 bytes left"},
        {patched(b, 268, std::uint32_t(0)), "m.bin: byte 268: animation 0 has no frames"},
        {patched(b, 268, std::uint32_t(5)), "m.bin: byte 268: 5 frames do not fit in the 64 bytes left"},
        {patched(b, 272, std::uint32_t(1)), "m.bin: byte 272: frame names image 1 of 1"},
        {patched(b, 276, std::int32_t(-1)), "m.bin: byte 276: frame x -1 is outside 0..16384"},
        {patched(b, 284, std::int32_t(0)), "m.bin: byte 284: an empty frame rect"},
        {patched(b, 292, std::int32_t(-1)), "m.bin: byte 292: frame duration -1 is outside 0..2147483647"},
        {patched(b, 308, std::int32_t(3)), "m.bin: byte 308: frame 1 is not the size of frame 0"},
        {patched(b, 320, std::uint32_t(5)), "m.bin: byte 320: 5 animated runs of draw 0 do not fit in the 12 bytes left"},
        {patched(b, 328, std::uint32_t(3)), "m.bin: byte 324: run of vertices 1 + 3 is not inside draw 0's 3"},
        {patched(b, 328, std::uint32_t(0)), "m.bin: byte 324: run of vertices 1 + 0 is not inside draw 0's 3"},
        {patched(b, 332, std::uint32_t(1)), "m.bin: byte 332: run names animation 1 of 1"},
        {b + "x", "m.bin: byte 336: 1 bytes after the animations"},
    };
    for (const auto& [bytes, expected] : cases) {
        const std::string error = binary_error(bytes);
        EXPECT_EQ(error.substr(0, expected.size()), expected) << error;
    }
    for (std::size_t n = 264; n < b.size(); ++n) EXPECT_NE(binary_error(b.substr(0, n)), "no error") << n;

    const std::pair<std::string, std::string> json_cases[] = {
        {replaced(text, "[{\"frames\": [{", "[{\"frames\": [], \"x\": [{"), "m.json: animations[0].frames: has no frames"},
        {replaced(text, "\"image\": 0, \"rect\": [0", "\"image\": 1, \"rect\": [0"), "m.json: animations[0].frames[0].image: must be an integer in 0..0"},
        {replaced(text, "[2, 0, 2, 2]", "[2, 0, 3, 2]"), "m.json: animations[0].frames[1].rect: is not the size of frame 0's"},
        {replaced(text, "[0, 0, 2, 2]", "[0, 0, 2]"), "m.json: animations[0].frames[0].rect: must be [x, y, w, h]"},
        {replaced(text, "\"duration\": 50", "\"duration\": -5"), "m.json: animations[0].frames[1].duration: must be an integer"},
        {replaced(text, "\"draw\": 0", "\"draw\": 1"), "m.json: animated[0].draw: must be an integer in 0..0"},
        {replaced(text, "\"vertex_count\": 2", "\"vertex_count\": 3"), "m.json: animated[0].vertex_count: must be an integer in 0..2"},
        {replaced(text, "\"vertex_count\": 2", "\"vertex_count\": 0"), "m.json: animated[0].vertex_count: must not be 0"},
        {replaced(text, "\"animation\": 0}", "\"animation\": 1}"), "m.json: animated[0].animation: must be an integer in 0..0"},
    };
    for (const auto& [t, expected] : json_cases) {
        const std::string error = json_error(t);
        EXPECT_EQ(error.substr(0, expected.size()), expected) << error;
    }
}

// A few thousand random byte edits of both forms: every outcome is a value
// or a depthcull::Error (the fuzz harnesses in fuzz/ run this without bound).
TEST(MeshReaders, RandomEditsNeverCrash) {
    const io::MeshesDocument small = io::meshes_from_json(kSmallJson, "m.json");
    const std::string forms[] = {kSmallJson, io::meshes_to_binary(small, "")};
    std::mt19937 rng(7);
    for (const std::string& form : forms) {
        for (int i = 0; i < 3000; ++i) {
            std::string s = form;
            for (int k = 0; k < 1 + int(rng() % 4); ++k) s[rng() % s.size()] = char(rng());
            try {
                io::MeshesDocument m = io::is_binary_meshes(s) ? io::meshes_from_binary(s, "x") : io::meshes_from_json(s, "x");
                for (const Draw& d : m.meshes.draws)
                    for (std::uint32_t index : d.indices) ASSERT_LT(index, d.vertex_count());
            } catch (const depthcull::Error&) {
            }
        }
    }
}

// The fuzz harnesses' seeds (fuzz/corpus/mesh_json, mesh_binary) are
// valid files, so fuzzing starts from inputs that reach every check; the
// inputs that once crashed a reader (crash-*) are kept beside them.
TEST(MeshReaders, FuzzSeedsAreValidMeshes) {
    int seeds = 0;
    for (const char* dir : {"mesh_json", "mesh_binary"}) {
        for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(DEPTHCULL_SOURCE_DIR) / "fuzz/corpus" / dir)) {
            if (entry.path().filename().string().rfind("crash-", 0) == 0) continue;
            io::MeshesDocument m = io::read_meshes(entry.path().string());
            EXPECT_FALSE(m.meshes.draws.empty()) << entry.path();
            ++seeds;
        }
    }
    EXPECT_GE(seeds, 4);
    // Both forms of a seed hold the same meshes.
    const std::string root = std::string(DEPTHCULL_SOURCE_DIR) + "/fuzz/corpus/";
    io::MeshesDocument j = io::read_meshes(root + "mesh_json/two_draws.json"), b = io::read_meshes(root + "mesh_binary/two_draws.bin");
    expect_same_meshes(j.meshes, b.meshes);
}

// Many insertion points over many blend draws, every point's blend_draw
// 0: the readers once walked the draws from each point's blend_draw to the
// end, points x draws (65,536 points over 131,072 draws, a 4 MB file, took
// 10 s; the checks of the 65,536 x 16,384 here 0.7 s, 0.01 s now). Each
// point after the first checks in constant time; the decisions and
// messages are the same.
io::MeshesDocument many_points_over_many_draws(std::size_t points, std::size_t draws) {
    io::MeshesDocument d;
    d.images = {SceneImage{"a", "a.png", 4, 4}};
    SceneMeshes& m = d.meshes;
    m.viewport = {0, 0, 64, 64};
    m.depth_test = true;
    m.draws.resize(draws); // blend draws without vertices
    m.stats.elements = 1;
    m.stats.draw_calls = std::int64_t(draws);
    m.stats.depth_levels = 1;
    m.stats.depth_bits = 10;
    m.depth_denominator = std::int64_t(1) << 8;
    m.insertion_points.assign(points, InsertionPoint{1, 0, 0, 0});
    return d;
}

TEST(MeshReaders, ManyInsertionPointsOverManyDrawsRead) {
    // The most points a file may hold (kMaxMeshInsertionPoints), binary
    // (the cheaper form to write and parse: the checks dominate).
    const io::MeshesDocument most = many_points_over_many_draws(io::kMaxMeshInsertionPoints, 16384);
    const io::MeshesDocument read = io::meshes_from_binary(io::meshes_to_binary(most, ""), "m.bin");
    EXPECT_EQ(read.meshes.insertion_points.size(), io::kMaxMeshInsertionPoints);
    EXPECT_EQ(read.meshes.draws.size(), 16384u);
    // Both forms share the checks: the same decisions, smaller.
    const io::MeshesDocument d = many_points_over_many_draws(4096, 2048);
    EXPECT_EQ(io::meshes_from_json(io::meshes_to_json(d, ""), "m.json").meshes.insertion_points.size(), 4096u);
    // An opaque draw after the points' blend_draw: refused at the first
    // point, naming the first such draw.
    io::MeshesDocument bad = d;
    bad.meshes.draws[1000].pass = Pass::opaque;
    bad.meshes.draws[2047].pass = Pass::opaque;
    const std::string error = binary_error(io::meshes_to_binary(bad, ""));
    EXPECT_EQ(error.find("m.bin: byte "), 0u) << error;
    EXPECT_NE(error.find(": insertion point 0: blend_draw 0 is not in the blend pass (draw 1000 is opaque)"), std::string::npos) << error;
    EXPECT_EQ(json_error(io::meshes_to_json(bad, "")),
              "m.json: insertion_points[0].blend_draw: blend_draw 0 is not in the blend pass (draw 1000 is opaque)");
    // Later points may not go back before a first one that passed.
    bad = d;
    bad.meshes.insertion_points[0].blend_draw = 2048;
    EXPECT_EQ(json_error(io::meshes_to_json(bad, "")), "m.json: insertion_points[1].blend_draw: blend_draw 0 is before the previous point's");
    // Points whose blend_draw grows, all past the one opaque draw: read.
    bad = d;
    bad.meshes.draws[0].pass = Pass::opaque;
    for (std::size_t k = 0; k < bad.meshes.insertion_points.size(); ++k) bad.meshes.insertion_points[k].blend_draw = std::uint32_t(1 + k / 2);
    EXPECT_EQ(io::meshes_from_binary(io::meshes_to_binary(bad, ""), "m.bin").meshes.insertion_points.back().blend_draw, 2048u);
}

} // namespace
} // namespace depthcull::test
