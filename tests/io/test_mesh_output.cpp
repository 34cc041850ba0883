// The meshes JSON and binary writers, and determinism of the whole
// pipeline across thread counts.
#include <algorithm>
#include <cstring>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "test_scene_json_helpers.h"

namespace depthcull::test {
namespace {

std::string write_scene(const SceneDir& dir) {
    dir.standard_art();
    std::string elements;
    for (int i = 0; i < 40; ++i) {
        if (i) elements += ",";
        elements += R"({"image": ")" + std::string(i % 3 ? "blob" : "tiles") + R"(", "rect": )" +
                    (i % 3 ? "[0, 0, 8, 8]" : (i % 2 ? "[8, 0, 8, 8]" : "[0, 0, 8, 8]")) + R"(, "transform": [1, 0, 0, 1, )" +
                    std::to_string((i * 7) % 50) + ", " + std::to_string((i * 5) % 30) + "]" +
                    (i % 5 == 0 ? R"(, "blend": "opaque")" : "") + "}";
    }
    return dir.write("scene.json", R"({"viewport": {"width": 64, "height": 48},
        "images": [{"id": "blob", "path": "art/blob.png"}, {"id": "tiles", "path": "art/tiles.png"}], "elements": [)" + elements + "]}");
}

SceneMeshes optimize(const pipeline::PreparedScene& p) {
    SceneMeshes m;
    EXPECT_EQ(reconstruct_scene(p.scene, p.analysis, {}, &m), ReconstructStatus::ok);
    return m;
}

// The mesh and scene writers share one path rule: relative to the output's
// directory, absolute when the two share nothing below "/".
TEST(MeshOutput, MeshAndSceneWritersRelativiseImagePathsAlike) {
    SceneDir dir("mesh_paths");
    pipeline::PreparedScene p = pipeline::prepare_scene(write_scene(dir), {});
    SceneMeshes m = optimize(p);
    std::filesystem::create_directories(dir.path("out"));
    for (const std::string& out : {dir.path("out/x.json"), std::string("/depthcull-no-such-dir/x.json")}) {
        nlohmann::json mesh = nlohmann::json::parse(io::meshes_to_json(io::meshes_document(p.scene, m), out));
        nlohmann::json scene = nlohmann::json::parse(io::scene_to_json_text(p.scene, out));
        EXPECT_EQ(mesh["images"][0]["path"], scene["images"][0]["path"]);
    }
    nlohmann::json far = nlohmann::json::parse(io::meshes_to_json(io::meshes_document(p.scene, m), "/depthcull-no-such-dir/x.json"));
    EXPECT_EQ(far["images"][0]["path"], std::filesystem::absolute(dir.path("art/blob.png")).lexically_normal().generic_string());
}

TEST(MeshOutput, JsonHasTheDocumentedShape) {
    SceneDir dir("mesh_json");
    pipeline::PreparedScene p = pipeline::prepare_scene(write_scene(dir), {});
    SceneMeshes m = optimize(p);
    std::filesystem::create_directories(dir.path("out"));
    io::write_meshes_json(dir.path("out/meshes.json"), io::meshes_document(p.scene, m));
    nlohmann::json j = nlohmann::json::parse(io::read_file(dir.path("out/meshes.json")));
    EXPECT_EQ(j["viewport"]["width"], 64);
    EXPECT_EQ(j["images"][0]["id"], "blob");
    EXPECT_EQ(j["images"][0]["path"], "../art/blob.png"); // relative to the output file
    ASSERT_EQ(j["draws"].size(), m.draws.size());
    std::int64_t triangles = 0;
    for (const auto& d : j["draws"]) {
        EXPECT_TRUE(d["pass"] == "opaque" || d["pass"] == "blend");
        EXPECT_EQ(d["vertices"].size() % kVertexFloats, 0u);
        EXPECT_EQ(d["indices"].size() % 3, 0u);
        for (const auto& i : d["indices"]) EXPECT_LT(i.get<std::size_t>(), d["vertices"].size() / kVertexFloats);
        triangles += std::int64_t(d["indices"].size() / 3);
    }
    EXPECT_EQ(j["stats"]["triangles"], triangles);
    EXPECT_EQ(j["stats"]["elements"], 40);
    EXPECT_EQ(j["stats"]["seconds"], 0);
    // Floats read back exactly.
    EXPECT_EQ(j["draws"][0]["vertices"][2].get<float>(), m.draws[0].vertices[2]);
}

TEST(MeshOutput, BinaryHeaderAndSize) {
    SceneDir dir("mesh_bin");
    pipeline::PreparedScene p = pipeline::prepare_scene(write_scene(dir), {});
    SceneMeshes m = optimize(p);
    std::string b = io::meshes_to_binary(io::meshes_document(p.scene, m), dir.path("meshes.bin"));
    ASSERT_GT(b.size(), 8u);
    EXPECT_EQ(std::memcmp(b.data(), "DCMESH\0\0", 8), 0);
    std::uint32_t images = 0, draws = 0;
    std::memcpy(&images, b.data() + 8 + 4 + 4 + 8 + 8 + 4 + 4, 4);
    std::memcpy(&draws, b.data() + 8 + 4 + 4 + 8 + 8 + 4 + 4 + 4, 4);
    EXPECT_EQ(images, 2u);
    EXPECT_EQ(draws, m.draws.size());
    std::size_t expected = 8 + 4 + 4 + 8 + 8 + 4 + 4 + 4 + 4 + 6 * 8 + 8;
    std::size_t payload = 0;
    for (const Draw& d : m.draws) payload += 16 + d.vertices.size() * 4 + d.indices.size() * 4;
    EXPECT_GT(b.size(), expected + payload);
}

TEST(MeshOutput, ByteIdenticalWhateverTheThreadCount) {
    SceneDir dir("mesh_threads");
    std::string scene = write_scene(dir);
    pipeline::PrepareOptions one, four;
    one.threads = 1;
    four.threads = 4;
    pipeline::PreparedScene a = pipeline::prepare_scene(scene, one), b = pipeline::prepare_scene(scene, four);
    std::string out = dir.path("m.json");
    EXPECT_EQ(io::meshes_to_json(io::meshes_document(a.scene, optimize(a)), out), io::meshes_to_json(io::meshes_document(b.scene, optimize(b)), out));
    EXPECT_EQ(io::meshes_to_binary(io::meshes_document(a.scene, optimize(a)), out), io::meshes_to_binary(io::meshes_document(b.scene, optimize(b)), out));
}

// Each form's three writers give one document's bytes: the streaming
// writers give the string writers' bytes, in pieces of about
// a MiB (never the whole file at once: a 125 MB meshes JSON would be a
// 125 MB string), and write_meshes_* write exactly those bytes.
TEST(MeshOutput, StreamedWritersGiveTheSameBytesInBoundedPieces) {
    SceneDir dir("mesh_stream");
    pipeline::PreparedScene p = pipeline::prepare_scene(write_scene(dir), {});
    SceneMeshes m = optimize(p);
    // A draw of 300,000 vertices: several MiB in either form.
    Draw big = m.draws.back();
    while (big.vertex_count() < 300000) {
        const std::size_t n = big.vertex_count();
        big.vertices.insert(big.vertices.end(), big.vertices.begin(), big.vertices.end());
        const std::size_t indices = big.indices.size();
        for (std::size_t k = 0; k < indices; ++k) big.indices.push_back(big.indices[k] + std::uint32_t(n));
    }
    m.draws.push_back(big);
    io::MeshesDocument document = io::meshes_document(p.scene, std::move(m));
    document.seconds = 0.5;
    const std::string out = dir.path("m.json");
    for (const bool binary : {false, true}) {
        std::string streamed;
        std::size_t pieces = 0, largest = 0;
        const io::WriteBytes collect = [&](std::string_view piece) {
            streamed += piece;
            ++pieces;
            largest = std::max(largest, piece.size());
        };
        binary ? io::stream_meshes_binary(collect, document, out) : io::stream_meshes_json(collect, document, out);
        const std::string whole = binary ? io::meshes_to_binary(document, out) : io::meshes_to_json(document, out);
        EXPECT_EQ(streamed, whole) << binary;
        EXPECT_GT(whole.size(), std::size_t(8) << 20) << binary;
        EXPECT_GT(pieces, binary ? 2u : 8u) << binary;
        // JSON: a MiB plus one vertex's text; binary: a draw's arrays go as
        // they are (the vertex array here is 10.8 MB).
        if (!binary) {
            EXPECT_LT(largest, (std::size_t(1) << 20) + 4096);
        }
        binary ? io::write_meshes_binary(out, document) : io::write_meshes_json(out, document);
        EXPECT_EQ(io::read_file(out), whole) << binary;
    }
}

} // namespace
} // namespace depthcull::test
