// The fuzz harnesses' seed corpora (fuzz/corpus/<harness>/: small real
// files and the inputs that once crashed a reader) replayed through the
// same readers in every build, sanitized or not: each input reads or fails
// with depthcull::Error, nothing else. And the regressions the fuzzers found.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <typeinfo>

#include <gtest/gtest.h>

#include "depthcull/io.h"
#include "pipeline/cache.h"
#include "io/formats.h"
#include "io/tiled_internal.h"
#include "test_scene_json_helpers.h"

namespace depthcull::test {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(DEPTHCULL_SOURCE_DIR) / "fuzz" / "corpus";

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// fn(bytes, name) for every seed of `harness`; any exception but
// depthcull::Error fails.
template <class F>
void replay(const std::string& harness, F&& fn) {
    int seeds = 0;
    for (const fs::directory_entry& e : fs::directory_iterator(kCorpus / harness)) {
        const std::string bytes = slurp(e.path());
        ++seeds;
        try {
            fn(bytes, e.path().filename().string());
        } catch (const depthcull::Error&) {
        } catch (const std::exception& ex) {
            ADD_FAILURE() << e.path() << ": " << typeid(ex).name() << ": " << ex.what();
        }
    }
    EXPECT_GT(seeds, 0) << "no seeds in " << (kCorpus / harness);
}

// Loading writes nothing (issue 12.4: colour keys are applied at decode,
// not by writing keyed copies): the seeds load with the cache pointed at a
// scratch directory, which must stay absent.
struct ScratchCache {
    SceneDir dir{"fuzz_corpus_cache"};
    std::string old = std::getenv("XDG_CACHE_HOME") ? std::getenv("XDG_CACHE_HOME") : "";
    ScratchCache() { ::setenv("XDG_CACHE_HOME", dir.path("cache").c_str(), 1); }
    ~ScratchCache() { old.empty() ? ::unsetenv("XDG_CACHE_HOME") : ::setenv("XDG_CACHE_HOME", old.c_str(), 1); }
};

TEST(FuzzCorpus, PngSeedsDecodeOrFailCleanly) {
    replay("png", [](const std::string& b, const std::string& name) { io::decode_png(b.data(), b.size(), name); });
    replay("analyze", [](const std::string& b, const std::string& name) { io::decode_png(b.data() + 1, b.size() - 1, name); });
}

TEST(FuzzCorpus, SceneJsonSeedsLoadOrFailCleanly) {
    replay("scene_json", [](const std::string& b, const std::string&) {
        io::scene_from_bytes(b, DEPTHCULL_SOURCE_DIR "/examples/fuzz.json");
    });
}

TEST(FuzzCorpus, TiledSeedsLoadOrFailCleanly) {
    ScratchCache cache;
    const std::string dir = DEPTHCULL_SOURCE_DIR "/tests/data/tiled/";
    replay("tiled_map", [&](const std::string& b, const std::string&) { io::scene_from_bytes(b, dir + "fuzz.tmx"); });
    replay("tiled_tileset", [&](const std::string& b, const std::string&) {
        std::vector<SceneImage> images;
        io::tiled::ImageTable table(images);
        io::guarded("fuzz.tsx", [&] { return io::tiled::tileset_from_bytes(b, dir + "fuzz.tsx", 1, table); });
    });
    // Templates are read through a map that names them.
    SceneDir maps("fuzz_corpus_templates");
    fs::copy_file(dir + "tiles.tsx", maps.path("tiles.tsx"));
    fs::copy_file(dir + "tiles.png", maps.path("tiles.png"));
    const std::string map = maps.write("m.tmx", R"(<map orientation="orthogonal" width="4" height="4" tilewidth="4" tileheight="4">
 <tileset firstgid="5" source="tiles.tsx"/>
 <objectgroup><object template="t.tx"/><object template="t.tx" gid="5" x="4" y="8" width="4" height="8" rotation="30"/></objectgroup>
</map>)");
    replay("tiled_template", [&](const std::string& b, const std::string&) {
        maps.write("t.tx", b);
        io::read_scene(map);
    });
    EXPECT_FALSE(fs::exists(cache.dir.path("cache"))) << "loading maps wrote into the cache directory";
}

// The cache-entry seeds are payloads of the current entry format (bytes
// 0-1 give the rect's size, as fuzz_cache_entry.cpp reads them): each one
// parses, so a format change that leaves them stale fails here instead of
// seeding the fuzzer with inputs its reader turns away at once.
TEST(FuzzCorpus, CacheEntrySeedsAreEntriesOfTheCurrentFormat) {
    int seeds = 0;
    for (const auto& e : fs::directory_iterator(kCorpus / "cache_entry")) {
        const std::string b = slurp(e.path());
        ASSERT_GE(b.size(), 2u) << e.path();
        const Rect rect{7, 3, 1 + static_cast<unsigned char>(b[0]) % 64, 1 + static_cast<unsigned char>(b[1]) % 64};
        const pipeline::CacheKey key = pipeline::hash_bytes_128(b.data(), 2);
        EXPECT_TRUE(pipeline::parse_analysis(pipeline::cache_entry(key, std::string_view(b).substr(2)), key, rect)) << e.path();
        ++seeds;
    }
    EXPECT_GT(seeds, 0);
}

TEST(FuzzCorpus, AtlasSeedsLoadOrFailCleanly) {
    replay("texturepacker", [](const std::string& b, const std::string&) { io::texturepacker_from_text(b, "atlas/fuzz.json"); });
}

TEST(FuzzCorpus, MeshSeedsReadOrFailCleanly) {
    replay("mesh_json", [](const std::string& b, const std::string& name) { io::meshes_from_json(b, name); });
    replay("mesh_binary", [](const std::string& b, const std::string& name) { io::meshes_from_binary(b, name); });
}

// ---- Regressions: what the fuzzers and sanitizers found (the inputs are
// also seeds, so the harnesses start from them).

// fuzz_mesh_binary: a draw of 0 vertices and 0 indices memcpy'd from the
// null data() of an empty vector (undefined even for 0 bytes; UBSan
// aborts). fuzz/corpus/mesh_binary/crash-empty-draw-memcpy.bin.
TEST(FuzzRegressions, BinaryMeshesWithAnEmptyDrawRead) {
    std::vector<SceneImage> images{{"a", "a.png", 4, 4}};
    SceneMeshes meshes;
    meshes.viewport = {0, 0, 8, 8};
    meshes.draws.push_back({});
    meshes.draws.back().image = 0;
    const io::MeshesDocument back = io::meshes_from_binary(io::meshes_to_binary({.images = images, .meshes = meshes}, ""), "empty.bin");
    ASSERT_EQ(back.meshes.draws.size(), 1u);
    EXPECT_TRUE(back.meshes.draws[0].vertices.empty());
    EXPECT_TRUE(back.meshes.draws[0].indices.empty());
    const std::string crash = slurp(kCorpus / "mesh_binary" / "crash-empty-draw-memcpy.bin");
    EXPECT_THROW(io::meshes_from_binary(crash, "crash.bin"), depthcull::Error);
}

// fuzz_mesh_binary: flags bit 1 (colour keys) set while no image had a
// key, or a key word with neither bit 24 nor 25 but colour bits: read,
// then written back differently (the form has one encoding per value).
// fuzz_mesh_binary: an image path "..tatr//iles.png", read from memory
// (kept as written), came back from the writer as "..tatr/iles.png": the
// path rule normalized a relative path written for stdout, so the file
// did not round-trip byte for byte. Relative paths written where the
// output's directory is the cwd are kept as given.
// fuzz/corpus/mesh_binary/crash-unnormal-relative-path.bin.
TEST(FuzzRegressions, RelativePathsWrittenForTheCwdAreKeptAsGiven) {
    const std::string crash = slurp(kCorpus / "mesh_binary" / "crash-unnormal-relative-path.bin");
    const io::MeshesDocument m = io::meshes_from_binary(crash, "crash.bin");
    EXPECT_EQ(m.images[1].path, "..tatr//iles.png");
    EXPECT_EQ(io::meshes_to_binary(m, ""), crash);
    EXPECT_EQ(io::meshes_from_json(io::meshes_to_json(m, ""), "m.json").images[1].path, "..tatr//iles.png");
    // A bare output file name is in the cwd too; elsewhere the rule relativises.
    EXPECT_EQ(io::meshes_to_binary(m, "m.bin"), crash);
    const std::string elsewhere = io::meshes_to_json(m, "sub/m.json");
    EXPECT_NE(elsewhere.find("\"../..tatr/iles.png\""), std::string::npos);
}

// fuzz/corpus/mesh_binary/crash-keys-flag-without-keys.bin.
TEST(FuzzRegressions, BinaryColourKeyWordsHaveOneEncoding) {
    const std::string crash = slurp(kCorpus / "mesh_binary" / "crash-keys-flag-without-keys.bin");
    try {
        io::meshes_from_binary(crash, "crash.bin");
        ADD_FAILURE() << "read";
    } catch (const depthcull::Error& e) {
        EXPECT_NE(std::string(e.what()).find("crash.bin: byte"), std::string::npos) << e.what();
    }
    std::vector<SceneImage> images{{"a", "a.png", 4, 4}};
    images[0].has_trans = true;
    images[0].trans = 0x00ff00;
    SceneMeshes meshes;
    meshes.viewport = {0, 0, 8, 8};
    std::string bytes = io::meshes_to_binary({.images = images, .meshes = meshes}, "");
    EXPECT_EQ(io::meshes_to_binary(io::meshes_from_binary(bytes, "k.bin"), ""), bytes);
    // The key word is the file's last 4 bytes here (no draws): drop bit 24.
    bytes[bytes.size() - 1] = 0;
    EXPECT_THROW(io::meshes_from_binary(bytes, "k.bin"), depthcull::Error);
}

// fuzz_mesh_json: a number too large for a double ("9e625610943") made
// nlohmann throw out_of_range past the reader, which caught parse_error
// only: a raw library exception instead of depthcull::Error.
// fuzz/corpus/mesh_json/crash-number-overflow.json.
TEST(FuzzRegressions, MeshJsonNumberOverflowIsAnIoError) {
    for (const std::string& text : {std::string(R"({"viewport": {"x": 1e400}})"), slurp(kCorpus / "mesh_json" / "crash-number-overflow.json")}) {
        try {
            io::meshes_from_json(text, "m.json");
            ADD_FAILURE() << "read " << text;
        } catch (const depthcull::Error& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.rfind("m.json: ", 0), 0u) << message;
            EXPECT_EQ(message.find("[json.exception"), std::string::npos) << message;
        }
    }
}

// fuzz_tiled_map: a staggered map of 4x1 tiles (Tiled's hexagonal
// renderer rounds tile sizes down to even: 0 high) got a 10x0 default
// viewport, which `import` wrote out as a scene no reader accepts.
// fuzz/corpus/tiled_map/crash-hex-zero-high-viewport.tmx.
TEST(FuzzRegressions, HexagonalMapOfOddTinyTilesHasAPositiveViewport) {
    const std::string dir = DEPTHCULL_SOURCE_DIR "/tests/data/tiled/";
    for (const char* axis : {"x", "y"}) {
        const std::string map = std::string(R"(<map orientation="hexagonal" width="3" height="3" tilewidth="1" tileheight="1" hexsidelength="0" staggeraxis=")") +
                                axis + R"(" staggerindex="even"><tileset firstgid="1" source="tiles.tsx"/></map>)";
        const Viewport v = io::scene_from_bytes(map, dir + "fuzz.tmx").viewport;
        EXPECT_GE(v.width, 1) << axis;
        EXPECT_GE(v.height, 1) << axis;
    }
    const Viewport v = io::scene_from_bytes(slurp(kCorpus / "tiled_map" / "crash-hex-zero-high-viewport.tmx"), dir + "fuzz.tmx").viewport;
    EXPECT_EQ(v.width, 10);
    EXPECT_EQ(v.height, 1);
}

} // namespace
} // namespace depthcull::test
