// Hostile and broken input (issue 11): each class of file that crashed us,
// ran away with memory or leaked a foreign exception is generated here and
// must load or fail with one depthcull::Error naming the file and the limit.
// Every test failed before its fix; none asserts a time (speed lives in
// benchmarks), but each would have taken gigabytes or crashed.
#include <gtest/gtest.h>
#include <zlib.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>

#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "depthcull/limits.h"
#include "pipeline/cache.h"
#include "io/formats.h"
#include "test_scene_json_helpers.h"

#include "testing/io_error.h"

namespace depthcull::test {
namespace {

namespace fs = std::filesystem;

// A PNG that is only a signature and an IHDR claiming w x h: what the map
// readers look at (png_size), 33 bytes.
std::string png_header(std::uint32_t w, std::uint32_t h) {
    std::string b("\x89PNG\r\n\x1a\n", 8);
    auto be32 = [&](std::uint32_t v) {
        for (int s = 24; s >= 0; s -= 8) b += char((v >> s) & 255);
    };
    be32(13);
    b += "IHDR";
    be32(w);
    be32(h);
    b += std::string("\x08\x06\x00\x00\x00", 5);
    be32(0); // CRC: not checked by png_size
    return b;
}

// A one-layer orthogonal map over `tileset` (a <tileset> element) with the
// given layer <data>.
std::string map_text(const std::string& tileset, const std::string& layers, const std::string& attrs = "") {
    return R"(<?xml version="1.0"?><map version="1.10" orientation="orthogonal" renderorder="right-down" width="2" height="1" tilewidth="8" tileheight="8" )" +
           attrs + ">" + tileset + layers + "</map>";
}

std::string one_cell(std::uint32_t gid) {
    return R"(<layer name="l" width="2" height="1"><data encoding="csv">)" + std::to_string(gid) + ",0</data></layer>";
}

// One gzip member of `bytes` (windowBits 31: a gzip header and trailer).
std::string gzip_member(std::string_view bytes) {
    z_stream z{};
    EXPECT_EQ(deflateInit2(&z, 9, Z_DEFLATED, 31, 8, Z_DEFAULT_STRATEGY), Z_OK);
    std::string out(deflateBound(&z, uLong(bytes.size())), '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    z.avail_in = uInt(bytes.size());
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = uInt(out.size());
    EXPECT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
    out.resize(z.total_out);
    deflateEnd(&z);
    return out;
}

// ---- 1. No crash

TEST(HostileTiled, TwentyThousandNestedGroupsAreRefusedNotAStackOverflow) {
    SceneDir dir("hostile_groups");
    dir.standard_art();
    std::string open, close;
    for (int i = 0; i < 20000; ++i) open += "<group>", close += "</group>";
    std::string tileset = R"(<tileset firstgid="1" name="t" tilewidth="8" tileheight="8"><image source="art/tiles.png" width="16" height="8"/></tileset>)";
    std::string path = dir.write("deep.tmx", map_text(tileset, open + one_cell(1) + close));
    std::string message = io_error([&] { io::read_scene(path); });
    EXPECT_TRUE(has(message, "deep.tmx") && has(message, "kMaxNestingDepth")) << message;
    // Nesting within the limit still draws.
    open.clear(), close.clear();
    for (int i = 0; i < 100; ++i) open += "<group>", close += "</group>";
    EXPECT_EQ(io::read_scene(dir.write("nested.tmx", map_text(tileset, open + one_cell(2) + close))).elements.size(), 1u);
}

TEST(HostileJson, DeepNestingIsRefusedInScenesAndAtlases) {
    SceneDir dir("hostile_json_depth");
    dir.standard_art();
    std::string deep(100000, '[');
    std::string scene = dir.write("deep.json", R"({"images": [], "elements": [], "extra": )" + deep + "}");
    std::string message = io_error([&] { io::read_scene(scene); });
    EXPECT_TRUE(has(message, "deep.json") && has(message, "kMaxNestingDepth")) << message;
    std::string atlas = dir.write("deep_atlas.json", R"({"frames": {}, "meta": {"image": "art/blob.png", "x": )" + deep + "}}");
    message = io_error([&] { io::read_atlas(atlas); });
    EXPECT_TRUE(has(message, "deep_atlas.json") && has(message, "kMaxNestingDepth")) << message;
    // Brackets inside strings do not count.
    std::string quoted = dir.write("quoted.json", R"({"images": [], "elements": [], "note": ")" + std::string(1000, '[') + "\"}");
    EXPECT_NO_THROW(io::read_scene(quoted));
}

TEST(HostileNumbers, NonFiniteViewportIsRefused) {
    SceneDir dir("hostile_viewport");
    dir.standard_art();
    std::string scene = dir.write("s.json", R"({"images": [{"id": "b", "path": "art/blob.png"}], "elements": [{"image": "b"}]})");
    for (double bad : {double(NAN), double(INFINITY), 1e300}) {
        io::LoadOptions o;
        o.has_viewport = true;
        o.viewport = {bad, 0, 64, 64};
        std::string message = io_error([&] { io::read_scene(scene, o); });
        EXPECT_TRUE(has(message, "viewport") && has(message, "kMaxCoordinate")) << message;
    }
    std::string far = dir.write("far.json", R"({"viewport": {"x": 1e300, "width": 8, "height": 8}, "images": [], "elements": []})");
    EXPECT_TRUE(has(io_error([&] { io::read_scene(far); }), "kMaxCoordinate"));
}

TEST(HostileNumbers, TiledOffsetsAndObjectsMustBeFiniteAndInRange) {
    SceneDir dir("hostile_tiled_numbers");
    dir.standard_art();
    std::string tileset = R"(<tileset firstgid="1" name="t" tilewidth="8" tileheight="8"><image source="art/tiles.png" width="16" height="8"/></tileset>)";
    std::string object = dir.write("object.tmx", map_text(tileset, R"(<objectgroup name="o"><object id="1" gid="1" x="1e300" y="0"/></objectgroup>)"));
    EXPECT_TRUE(has(io_error([&] { io::read_scene(object); }), "kMaxCoordinate"));
    std::string offset = dir.write("offset.tmx", map_text(R"(<tileset firstgid="1" name="t" tilewidth="8" tileheight="8"><tileoffset x="nan" y="0"/><image source="art/tiles.png" width="16" height="8"/></tileset>)", one_cell(1)));
    EXPECT_TRUE(has(io_error([&] { io::read_scene(offset); }), "tileoffset"));
    std::string layer = dir.write("layer.tmx", map_text(tileset, R"(<layer name="l" width="2" height="1" offsetx="inf"><data encoding="csv">1,0</data></layer>)"));
    EXPECT_TRUE(has(io_error([&] { io::read_scene(layer); }), "kMaxCoordinate"));
}

TEST(HostileNumbers, SpacingAndMarginNearIntMaxAreRefused) {
    SceneDir dir("hostile_spacing");
    dir.standard_art();
    for (const char* attr : {"spacing=\"2147483647\"", "margin=\"2147483000\"", "spacing=\"2147483640\" margin=\"2147483640\""}) {
        std::string tileset = std::string(R"(<tileset firstgid="1" name="t" tilewidth="8" tileheight="8" )") + attr +
                              R"(><image source="art/tiles.png" width="16" height="8"/></tileset>)";
        std::string message = io_error([&] { io::read_scene(dir.write("m.tmx", map_text(tileset, one_cell(1)))); });
        EXPECT_TRUE(has(message, "margin and spacing") && has(message, "kMaxImageSide")) << message;
    }
}

std::string infinite_map(const std::string& orientation, const std::string& chunks) {
    return R"(<?xml version="1.0"?><map orientation=")" + orientation +
           R"(" renderorder="right-down" width="2" height="2" tilewidth="8" tileheight="8" infinite="1">)"
           R"(<tileset firstgid="1" name="t" tilewidth="8" tileheight="8"><image source="art/tiles.png" width="16" height="8"/></tileset>)"
           R"(<layer name="l" width="2" height="2"><data encoding="csv">)" +
           chunks + "</data></layer></map>";
}

TEST(HostileNumbers, ChunksNearIntMaxAreRefusedOnOrthogonalAndIsometricMaps) {
    SceneDir dir("hostile_chunks");
    dir.standard_art();
    for (const char* orientation : {"orthogonal", "isometric", "staggered"}) {
        for (const char* at : {R"(x="2147483646" y="0")", R"(x="0" y="-2147483648")", R"(x="2147483000" y="2147483000")"}) {
            std::string chunk = std::string("<chunk ") + at + R"( width="2" height="1">1,2</chunk>)";
            std::string path = dir.write("far.tmx", infinite_map(orientation, chunk));
            std::string message = io_error([&] { io::read_scene(path); });
            EXPECT_TRUE(has(message, "kMaxMapSide")) << orientation << " " << at << ": " << message;
        }
        // At the limit's edge the tiles land where Tiled puts them.
        std::string path = dir.write("edge.tmx", infinite_map(orientation, R"(<chunk x="1048574" y="-1048576" width="2" height="1">1,2</chunk>)"));
        Scene s = io::read_scene(path);
        ASSERT_EQ(s.elements.size(), 2u) << orientation;
        for (const Element& e : s.elements)
            for (double t : e.transform) EXPECT_TRUE(std::isfinite(t));
        if (std::string(orientation) == "orthogonal") {
            EXPECT_EQ(s.elements[0].transform[4], 1048574.0 * 8);
        }
    }
}

// ---- 2. Every error is ours

TEST(HostileErrors, HugeJsonNumbersAreOurError) {
    SceneDir dir("hostile_1e400");
    dir.standard_art();
    std::string scene = dir.write("s.json", R"({"images": [{"id": "b", "path": "art/blob.png"}], "elements": [{"image": "b", "transform": [1e400, 0, 0, 1, 0, 0]}]})");
    std::string message = io_error([&] { io::read_scene(scene); });
    EXPECT_TRUE(has(message, "s.json") && !has(message, "[json.exception")) << message;
    std::string atlas = dir.write("a.json", R"({"frames": {"f": {"frame": {"x": 1e400, "y": 0, "w": 1, "h": 1}}}, "meta": {"image": "art/blob.png"}})");
    message = io_error([&] { io::read_atlas(atlas); });
    EXPECT_TRUE(has(message, "a.json") && !has(message, "[json.exception")) << message;
}

TEST(HostileErrors, InvalidUtf8PathsAreOurErrorWhenWrittenAsJson) {
    Scene scene;
    scene.viewport = {0, 0, 8, 8};
    scene.images.push_back({"tile", "/tmp/bad\xff\xfe.png", 8, 8});
    std::string message = io_error([&] { io::scene_to_json_text(scene, "out.json"); });
    EXPECT_TRUE(has(message, "out.json") && has(message, "not valid UTF-8")) << message;
    message = io_error([&] { io::meshes_to_json(io::meshes_document(scene, SceneMeshes{}), "out.json"); });
    EXPECT_TRUE(has(message, "out.json") && has(message, "not valid UTF-8")) << message;
    scene.images[0].path = "/tmp/caf\xc3\xa9.png"; // valid: written as is
    EXPECT_NO_THROW(io::scene_to_json_text(scene, "out.json"));
}

TEST(HostileErrors, Utf8CheckRejectsEveryMalformedForm) {
    EXPECT_TRUE(io::valid_utf8("plain ascii"));
    EXPECT_TRUE(io::valid_utf8("\xc3\xa9\xe2\x82\xac\xf0\x9f\x98\x80"));
    for (const char* bad : {"\xff", "\xc3", "\xe2\x82", "\xc0\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80", "\x80"})
        EXPECT_FALSE(io::valid_utf8(bad)) << bad;
}

TEST(HostileErrors, ForeignExceptionsBecomeIoErrorsNamingTheFile) {
    auto alloc = [] { return io::guarded("big.png", []() -> int { throw std::bad_alloc(); }); };
    EXPECT_TRUE(has(io_error(alloc), "big.png: out of memory"));
    auto other = [] { return io::guarded("x.json", []() -> int { throw std::length_error("vector"); }); };
    EXPECT_EQ(io_error(other), "x.json: vector");
}

// ---- 3. Bounded memory

TEST(HostileMemory, HugeTilesetOfOneTexelTilesIsNotTabulated) {
    SceneDir dir("hostile_tileset");
    std::ofstream(dir.path("art/huge.png"), std::ios::binary) << png_header(16384, 16384);
    std::string tileset = R"(<tileset firstgid="1" name="t" tilewidth="1" tileheight="1"><image source="art/huge.png" width="16384" height="16384"/></tileset>)";
    // The largest gid (2^28 - 1: the bits above are flags) names the
    // tile before the last.
    std::string path = dir.write("m.tmx", map_text(tileset, one_cell(0x0fffffffu)));
    // Before: a 268M-entry tile table (over 5 GB) was built first.
    Scene s = io::read_scene(path);
    ASSERT_EQ(s.elements.size(), 1u);
    EXPECT_EQ(s.elements[0].rect, (Rect{16382, 16383, 1, 1}));
}

TEST(HostileMemory, LargestTileIdIsSparse) {
    SceneDir dir("hostile_tile_id");
    dir.standard_art();
    std::string tileset = R"(<tileset firstgid="1" name="c" tilewidth="8" tileheight="8"><tile id="16777215"><image source="art/blob.png" width="8" height="8"/></tile></tileset>)";
    Scene s = io::read_scene(dir.write("m.tmx", map_text(tileset, one_cell(16777216))));
    ASSERT_EQ(s.elements.size(), 1u);
    EXPECT_EQ(s.elements[0].rect, (Rect{0, 0, 8, 8}));
    std::string message = io_error([&] { io::read_scene(dir.write("n.tmx", map_text(tileset, one_cell(5)))); });
    EXPECT_TRUE(has(message, "gid 5 is out of range")) << message;
}

std::string base64(const std::string& bytes) {
    static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t v = std::uint32_t(std::uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= std::uint8_t(bytes[i + 2]);
        out += digits[v >> 18];
        out += digits[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? digits[v & 63] : '=';
    }
    return out;
}

TEST(HostileMemory, OverlappingChunksCountEveryCell) {
    SceneDir dir("hostile_overlap");
    dir.standard_art();
    // Chunks of 4096x4096 empty cells at one place, zlib-compressed (each
    // 64 MB decoded; before, 64 of them were held at once: 4.2 GB). The
    // first fills the layer limit exactly; the second is refused before
    // it is decoded.
    std::string zeros(std::size_t(4096) * 4096 * 4, '\0');
    std::string packed(compressBound(uLong(zeros.size())), '\0');
    uLongf packed_size = uLongf(packed.size());
    ASSERT_EQ(compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, reinterpret_cast<const Bytef*>(zeros.data()),
                        uLong(zeros.size()), 1),
              Z_OK);
    packed.resize(packed_size);
    std::string chunk = R"(<chunk x="-2048" y="-2048" width="4096" height="4096">)" + base64(packed) + "</chunk>";
    std::string chunks;
    for (int k = 0; k < 4; ++k) chunks += chunk; // 64 in the measured file; the second is refused
    std::string text = infinite_map("orthogonal", chunks);
    text.replace(text.find(R"(encoding="csv")"), 14, R"(encoding="base64" compression="zlib")");
    std::string message = io_error([&] { io::read_scene(dir.write("m.tmx", text)); });
    EXPECT_TRUE(has(message, "chunk 1") && has(message, "kMaxLayerCells")) << message;
}

TEST(HostileMemory, NonRegularFilesAreRefusedAsEveryInput) {
    SceneDir dir("hostile_devzero");
    dir.standard_art();
    ASSERT_EQ(::mkfifo(dir.path("fifo.json").c_str(), 0600), 0);
    fs::create_symlink("/dev/zero", dir.path("zero.json"));
    fs::create_symlink("/dev/zero", dir.path("zero.tmx"));
    fs::create_symlink("/dev/zero", dir.path("art/zero.png"));
    fs::create_symlink("/dev/zero", dir.path("zero.tsx"));
    fs::create_symlink("/dev/zero", dir.path("zero.tx"));
    for (const char* input : {"fifo.json", "zero.json", "zero.tmx"})
        EXPECT_TRUE(has(io_error([&] { io::read_scene(dir.path(input)); }), "not a regular file")) << input;
    EXPECT_TRUE(has(io_error([&] { io::read_atlas(dir.path("zero.json")); }), "not a regular file"));
    EXPECT_TRUE(has(io_error([&] { io::read_png(dir.path("art/zero.png")); }), "not a regular file"));
    std::string scene = dir.write("s.json", R"({"images": [{"id": "z", "path": "art/zero.png"}], "elements": []})");
    EXPECT_TRUE(has(io_error([&] { io::read_scene(scene); }), "not a regular file"));
    std::string tsx = dir.write("tsx.tmx", map_text(R"(<tileset firstgid="1" source="zero.tsx"/>)", one_cell(1)));
    EXPECT_TRUE(has(io_error([&] { io::read_scene(tsx); }), "not a regular file"));
    std::string tx = dir.write("tx.tmx", map_text(R"(<tileset firstgid="1" name="t" tilewidth="8" tileheight="8"><image source="art/tiles.png" width="16" height="8"/></tileset>)",
                                                  R"(<objectgroup name="o"><object id="1" template="zero.tx"/></objectgroup>)"));
    EXPECT_TRUE(has(io_error([&] { io::read_scene(tx); }), "not a regular file"));
}

TEST(HostileMemory, AtlasFramesAreFoundByName) {
    SceneDir dir("hostile_atlas");
    dir.standard_art();
    std::string frames;
    for (int i = 0; i < 2000; ++i)
        frames += (i ? "," : "") + std::string("\"f") + std::to_string(i) + R"(": {"frame": {"x": 0, "y": 0, "w": 1, "h": 1}})";
    io::Atlas atlas = io::read_atlas(dir.write("a.json", R"({"frames": {)" + frames + R"(}, "meta": {"image": "art/blob.png"}})"));
    EXPECT_EQ(atlas.by_name.size(), 2000u);
    ASSERT_NE(atlas.find("f1999"), nullptr);
    EXPECT_EQ(atlas.find("f1999")->name, "f1999");
    EXPECT_EQ(atlas.find("f2000"), nullptr);
    // An Atlas built by hand (no index) is searched linearly.
    io::Atlas manual;
    manual.frames.push_back(atlas.frames[5]);
    ASSERT_NE(manual.find("f5"), nullptr);
    EXPECT_EQ(manual.find("f6"), nullptr);
}

TEST(HostileMemory, AtlasHashKeepsFileOrderAndRefusesDuplicateNames) {
    // Parsed with std::map objects (ordered_json took 30 s on 200,000
    // frames); the file order is recorded separately and must survive.
    SceneDir dir("hostile_atlas_order");
    dir.standard_art();
    auto frame = [](const char* name) { return std::string("\"") + name + R"(": {"frame": {"x": 0, "y": 0, "w": 1, "h": 1}})"; };
    io::Atlas atlas = io::read_atlas(
        dir.write("a.json", "{\"frames\": {" + frame("zeta") + "," + frame("alpha") + "," + frame("mid") + R"(}, "meta": {"image": "art/blob.png"}})"));
    ASSERT_EQ(atlas.frames.size(), 3u);
    EXPECT_EQ(atlas.frames[0].name, "zeta");
    EXPECT_EQ(atlas.frames[1].name, "alpha");
    EXPECT_EQ(atlas.frames[2].name, "mid");
    std::string e = io_error([&] {
        io::read_atlas(dir.write("d.json", "{\"frames\": {" + frame("a") + "," + frame("a") + R"(}, "meta": {"image": "art/blob.png"}})"));
    });
    EXPECT_TRUE(has(e, "d.json")) << e;
    EXPECT_TRUE(has(e, "duplicate frame name")) << e;
}

TEST(HostileErrors, MeshJsonHugeNumbersAndDeepNestingAreOurErrors) {
    std::string e = io_error([] { io::meshes_from_json(R"({"viewport": [0, 0, 1e400, 1]})", "m.json", "."); });
    EXPECT_TRUE(has(e, "m.json")) << e;
    e = io_error([] { io::meshes_from_json(std::string(100000, '[') + std::string(100000, ']'), "deep.json", "."); });
    EXPECT_TRUE(has(e, "deep.json")) << e;
}

// The system reads a file name up to its first NUL: "blob.png\u0000.txt"
// was optimized as blob.png, under the other name.
TEST(HostileErrors, ANulInAFileNameIsRefused) {
    SceneDir dir("hostile_nul");
    dir.standard_art();
    const std::string scene = dir.write("s.json", R"({"images": [{"id": "b", "path": "art/blob.png\u0000.txt"}], "elements": [{"image": "b"}]})");
    pipeline::PrepareOptions o;
    o.cache_dir = "";
    const std::string e = io_error([&] { pipeline::prepare_scene(scene, o); });
    EXPECT_TRUE(has(e, "blob.png\\0.txt: a file name cannot hold a NUL character")) << e;
    EXPECT_EQ(e.find('\0'), std::string::npos);
}

// gunzip joins the members of a gzip file (`cat a.gz b.gz`); only the
// first was read, and the map was refused as cut short. Their total is
// still bounded as one file's.
TEST(HostileTiled, GzipMembersOfAMapAreJoined) {
    SceneDir dir("hostile_gzip_members");
    dir.standard_art();
    const std::string tileset = R"(<tileset firstgid="1" name="t" tilewidth="8" tileheight="8"><image source="art/tiles.png" width="16" height="8"/></tileset>)";
    const std::string text = map_text(tileset, one_cell(2));
    const std::size_t half = text.size() / 2;
    const std::string whole = dir.write("whole.tmx.gz", gzip_member(text));
    const std::string joined = dir.write("joined.tmx.gz", gzip_member(text.substr(0, half)) + gzip_member(text.substr(half)));
    EXPECT_EQ(io::read_scene(joined).elements.size(), 1u);
    EXPECT_EQ(io::scene_to_json_text(io::read_scene(joined), ""), io::scene_to_json_text(io::read_scene(whole), ""));
    // Bytes after the last member that are no gzip member: as before, ignored.
    EXPECT_EQ(io::read_scene(dir.write("tail.tmx.gz", gzip_member(text) + "junk")).elements.size(), 1u);
}

// ---- 4. Caches heal

TEST(HostileCache, EntriesThatFailStructuralChecksAreMissesAndRewritten) {
    SceneDir dir("hostile_cache");
    dir.standard_art();
    std::string scene = dir.write("s.json", R"({"images": [{"id": "b", "path": "art/blob.png"}], "elements": [{"image": "b"}]})");
    pipeline::PrepareOptions o;
    o.cache_dir = dir.path("cache");
    pipeline::PreparedScene first = pipeline::prepare_scene(scene, o);
    ASSERT_EQ(first.analyzed, 1);
    const ImageAnalysis good = first.analysis.images[0];
    const pipeline::CacheKey key = pipeline::analysis_key(first.view(0), good.rect, o.analyze);
    const std::string entry = pipeline::cache_entry_path(o.cache_dir, key);
    // Damaged before it was summed: the checksum matches, the content lies.
    auto corrupt = [&](auto&& damage) {
        ImageAnalysis bad = good;
        damage(bad);
        std::ofstream(entry, std::ios::binary | std::ios::trunc) << pipeline::serialize_analysis(key, bad);
        EXPECT_FALSE(pipeline::parse_analysis(pipeline::serialize_analysis(key, bad), key, good.rect));
        pipeline::PreparedScene run = pipeline::prepare_scene(scene, o);
        EXPECT_EQ(run.analyzed, 1);
        EXPECT_EQ(run.analysis.images[0].boundary, good.boundary);
        std::ifstream in(entry, std::ios::binary);
        EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), pipeline::serialize_analysis(key, run.analysis.images[0])) << "rewritten";
        EXPECT_EQ(pipeline::prepare_scene(scene, o).cache_hits, 1);
    };
    corrupt([](ImageAnalysis& a) { a.boundary[0][0].x = NAN; });
    corrupt([](ImageAnalysis& a) { a.boundary[0][1].y = 1e12; });          // far outside the rect
    corrupt([](ImageAnalysis& a) { a.opaque.push_back({{-5, -5}, {0, -5}, {0, 0}}); });
    corrupt([](ImageAnalysis& a) { a.stats.opaque_texels = -1; });
    corrupt([](ImageAnalysis& a) { a.stats.nontransparent_texels = 1 << 30; }); // more than the rect holds
    corrupt([](ImageAnalysis& a) { a.stats.boundary_area = INFINITY; });
    corrupt([](ImageAnalysis& a) { a.boundary[0].resize(2); });             // no polygon has fewer than 3 vertices
    corrupt([](ImageAnalysis& a) { a.opaque.push_back({}); });
}

// A link planted where an entry belongs made the store replace its target
// (the scene itself here), on every run; a FIFO there blocked the run. Both
// are misses now, and the store puts a regular entry in their place.
TEST(HostileCache, LinksAndFifosWhereAnEntryBelongsAreReplacedNotFollowed) {
    SceneDir dir("hostile_cache_links");
    dir.standard_art();
    const std::string scene = dir.write("s.json", R"({"images": [{"id": "b", "path": "art/blob.png"}], "elements": [{"image": "b"}]})");
    const std::string scene_text = io::read_file(scene);
    pipeline::PrepareOptions o;
    o.cache_dir = dir.path("cache");
    pipeline::PreparedScene first = pipeline::prepare_scene(scene, o);
    const pipeline::CacheKey key = pipeline::analysis_key(first.view(0), first.analysis.images[0].rect, o.analyze);
    const std::string entry = pipeline::cache_entry_path(o.cache_dir, key);
    auto regular_entry = [&] {
        struct stat st;
        return ::lstat(entry.c_str(), &st) == 0 && S_ISREG(st.st_mode);
    };
    std::filesystem::remove(entry);
    std::filesystem::create_symlink(scene, entry);
    pipeline::PreparedScene linked = pipeline::prepare_scene(scene, o);
    EXPECT_EQ(linked.analyzed, 1);
    EXPECT_EQ(io::read_file(scene), scene_text);
    EXPECT_TRUE(regular_entry());
    EXPECT_EQ(pipeline::prepare_scene(scene, o).cache_hits, 1);

    std::filesystem::remove(entry);
    ASSERT_EQ(::mkfifo(entry.c_str(), 0600), 0);
    EXPECT_EQ(pipeline::prepare_scene(scene, o).analyzed, 1); // returns: neither read nor written in place
    EXPECT_TRUE(regular_entry());
}

TEST(HostileCache, CountsBeyondTheBytesLeftAreRefusedBeforeAllocating) {
    ImageAnalysis a;
    a.rect = {0, 0, 4, 4};
    const pipeline::CacheKey key = pipeline::hash_bytes_128("k", 1);
    std::string bytes = pipeline::serialize_analysis(key, a);
    // Payload: w, h, boundary count. Claim a million polygons in an entry
    // of a few bytes, and re-sum it so only the structure can tell.
    const std::size_t header = 4 + 4 + 16 + 8;
    std::uint32_t many = 1u << 20;
    std::memcpy(bytes.data() + header + 8, &many, 4);
    std::string payload = bytes.substr(header, bytes.size() - header - 8);
    std::uint64_t sum = pipeline::hash_bytes_128(payload.data(), payload.size(), 1).words[0];
    std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
    EXPECT_FALSE(pipeline::parse_analysis(bytes, key, a.rect));
}

// ---- 5. Files

TEST(HostileFiles, StaleTemporariesOfDeadWritersAreRemoved) {
    SceneDir dir("hostile_temps");
    pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    ASSERT_GT(child, 0);
    ::waitpid(child, nullptr, 0); // its pid now names no process (until reused, which the test tolerates)
    std::string dead = dir.write(".out.json.tmp." + std::to_string(child) + ".0", "half");
    std::string alive = dir.write(".out.json.tmp." + std::to_string(::getpid()) + ".999", "ours");
    std::string other = dir.write(".other.json.tmp." + std::to_string(child) + ".0", "not beside out.json");
    io::write_file_atomic(dir.path("out.json"), "{}");
    EXPECT_FALSE(fs::exists(dead));
    EXPECT_TRUE(fs::exists(alive)); // a live writer's (here: this process's) temporary is kept
    EXPECT_TRUE(fs::exists(other));
    std::ifstream in(dir.path("out.json"));
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "{}");
}

TEST(HostileFiles, SameFileComparesIdentityAndCanonicalPaths) {
    SceneDir dir("hostile_same");
    std::string a = dir.write("a.json", "{}");
    EXPECT_TRUE(io::same_file(a, a));
    EXPECT_TRUE(io::same_file(a, dir.path("art/../a.json")));
    fs::create_hard_link(a, dir.path("hard.json"));
    fs::create_symlink(a, dir.path("soft.json"));
    EXPECT_TRUE(io::same_file(a, dir.path("hard.json")));
    EXPECT_TRUE(io::same_file(dir.path("soft.json"), a));
    EXPECT_FALSE(io::same_file(a, dir.path("b.json")));
    EXPECT_TRUE(io::same_file(dir.path("new.json"), dir.path("art/../new.json"))); // neither exists yet
    EXPECT_FALSE(io::same_file("-", "-"));
    EXPECT_FALSE(io::same_file("", ""));
}

} // namespace
} // namespace depthcull::test
