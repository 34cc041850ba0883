// Tiled maps: hand-written maps in tests/data/tiled with exact expected
// scenes, one feature at a time, and the one-line errors for bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "depthcull/io.h"
#include "testing/corpus.h"
#include "tiled_expect.h"

using namespace depthcull;
namespace fs = std::filesystem;

namespace {

using test::T;
using test::data;
using test::expect_element;
using test::expect_flips_map;

// A map written to a temporary directory; image sources may name the test
// data by absolute path.
struct TempMap {
    fs::path dir;
    std::string path;
    TempMap(const std::string& name, const std::string& text) {
        dir = fs::temp_directory_path() / ("dc_tiled_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                                           ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir);
        path = (dir / name).string();
        std::ofstream(path, std::ios::binary) << text;
    }
    ~TempMap() {
        std::error_code ec;
        fs::remove_all(dir, ec);
    }
};

std::string tileset_xml(const std::string& extra_image_attrs = "") {
    return "<tileset firstgid=\"1\" name=\"tiles\" tilewidth=\"4\" tileheight=\"4\" spacing=\"1\" margin=\"1\">"
           "<image source=\"" + data("tiles.png") + "\"" + extra_image_attrs + "/></tileset>";
}

std::string map_xml(const std::string& body, const std::string& map_attrs = "orientation=\"orthogonal\" width=\"3\" height=\"2\"",
                    const std::string& tileset = tileset_xml()) {
    return "<?xml version=\"1.0\"?><map version=\"1.10\" " + map_attrs + " tilewidth=\"4\" tileheight=\"4\">" + tileset + body + "</map>";
}

std::string layer_xml(const std::string& data_xml) { return "<layer name=\"ground\" width=\"3\" height=\"2\">" + data_xml + "</layer>"; }

std::string load_error(const std::string& path) {
    try {
        io::read_scene(path);
    } catch (const depthcull::Error& e) {
        return e.what();
    }
    return "(no error)";
}

} // namespace

TEST(Tiled, CsvLayerWithFlips) { expect_flips_map(io::read_scene(data("csv.tmx"))); }
TEST(Tiled, Base64Layer) { expect_flips_map(io::read_scene(data("base64.tmx"))); }
TEST(Tiled, Base64ZlibLayer) { expect_flips_map(io::read_scene(data("zlib.tmx"))); }
TEST(Tiled, Base64GzipLayer) { expect_flips_map(io::read_scene(data("gzip.tmx"))); }
TEST(Tiled, XmlTileLayer) { expect_flips_map(io::read_scene(data("xml.tmx"))); }
TEST(Tiled, ExternalTileset) { expect_flips_map(io::read_scene(data("external.tmx"))); }
TEST(Tiled, GzippedExternalTileset) { expect_flips_map(io::read_scene(data("external_gz.tmx"))); }
TEST(Tiled, GzippedMap) { expect_flips_map(io::read_scene(data("whole.tmx.gz"))); }

TEST(Tiled, ImagePathsResolveRelativeToTheMap) {
    Scene s = io::read_scene(data("external.tmx"));
    EXPECT_TRUE(fs::equivalent(s.images[0].path, data("tiles.png")));
}

TEST(Tiled, ViewportCullsElements) {
    io::LoadOptions options;
    options.has_viewport = true;
    options.viewport = {4, 0, 4, 4};
    Scene s = io::read_scene(data("csv.tmx"), options);
    EXPECT_EQ(s.viewport.x, 4);
    EXPECT_EQ(s.viewport.width, 4);
    // Only the flipped tile at cell (1, 0) touches [4, 8) x [0, 4) with area.
    ASSERT_EQ(s.elements.size(), 1u);
    expect_element(s, 0, "tiles", {6, 1, 4, 4}, {-1, 0, 0, 1, 8, 0});
}

TEST(Tiled, TileObjectsGroupsOpacityTint) {
    Scene s = io::read_scene(data("objects.tmx"));
    ASSERT_EQ(s.images.size(), 2u);
    EXPECT_EQ(s.images[0].id, "a");
    EXPECT_EQ(s.images[1].id, "b");
    EXPECT_EQ(s.viewport.width, 80);
    ASSERT_EQ(s.elements.size(), 4u);
    // Group offset (10, 20), opacity 0.5 * 0.5, tint #ff8000.
    const std::array<float, 4> tinted{1, float(128 / 255.0), 0, 0.25f};
    // topdown: object 2 (y 10) before object 1 (y 30); 12x4 scales b.png 2x.
    expect_element(s, 0, "b", {0, 0, 6, 2}, {2, 0, 0, 2, 15, 26}, tinted);
    expect_element(s, 1, "a", {0, 0, 3, 5}, {1, 0, 0, 1, 10, 45}, tinted);
    // index order; rotation 90 clockwise about the object's bottom-left (8, 40).
    expect_element(s, 2, "a", {0, 0, 3, 5}, {0, 1, -1, 0, 13, 40});
    // horizontal flip about the object's centre.
    expect_element(s, 3, "a", {0, 0, 3, 5}, {-1, 0, 0, 1, 4, 1});
}

TEST(Tiled, IsometricDrawsByScreenRows) {
    Scene s = io::read_scene(data("iso.tmx"));
    EXPECT_EQ(s.viewport.width, 16);
    EXPECT_EQ(s.viewport.height, 8);
    ASSERT_EQ(s.elements.size(), 4u);
    expect_element(s, 0, "tiles", {1, 1, 4, 4}, {1, 0, 0, 1, 4, 0}); // (0,0)
    expect_element(s, 1, "tiles", {1, 6, 4, 4}, {1, 0, 0, 1, 0, 2}); // (0,1)
    expect_element(s, 2, "tiles", {6, 1, 4, 4}, {1, 0, 0, 1, 8, 2}); // (1,0)
    expect_element(s, 3, "tiles", {6, 6, 4, 4}, {1, 0, 0, 1, 4, 4}); // (1,1)
}

TEST(Tiled, TallTilesOffsetsAndRenderOrder) {
    Scene s = io::read_scene(data("tall.tmx"));
    ASSERT_EQ(s.elements.size(), 2u);
    // left-up: column 1 first. Bottom of cell 4, + layer 0.5, + tileoffset -2 = 2.5; top = 2.5 - 8.
    expect_element(s, 0, "tall", {0, 0, 4, 8}, {1, 0, 0, 1, 7, -5.5}, {1, 1, 1, 0.5f});
    expect_element(s, 1, "tall", {0, 0, 4, 8}, {1, 0, 0, 1, 3, -5.5}, {1, 1, 1, 0.5f});
}

TEST(Tiled, RightUpRenderOrder) {
    TempMap m("ru.tmx", map_xml(layer_xml("<data encoding=\"csv\">1,2,3,4,1,2</data>"),
                               "orientation=\"orthogonal\" renderorder=\"right-up\" width=\"3\" height=\"2\""));
    Scene s = io::read_scene(m.path);
    ASSERT_EQ(s.elements.size(), 6u);
    expect_element(s, 0, "tiles", {6, 6, 4, 4}, {1, 0, 0, 1, 0, 4});  // row 1 first
    expect_element(s, 3, "tiles", {1, 1, 4, 4}, {1, 0, 0, 1, 0, 0});
}

TEST(Tiled, AnimatedTileDrawsItsFirstFrame) {
    std::string ts = "<tileset firstgid=\"1\" name=\"tiles\" tilewidth=\"4\" tileheight=\"4\" spacing=\"1\" margin=\"1\"><image source=\"" +
                     data("tiles.png") + "\"/><tile id=\"0\"><animation><frame tileid=\"3\" duration=\"100\"/>"
                     "<frame tileid=\"0\" duration=\"100\"/></animation></tile></tileset>";
    TempMap m("anim.tmx", map_xml(layer_xml("<data encoding=\"csv\">1,0,0,0,0,0</data>"), "orientation=\"orthogonal\" width=\"3\" height=\"2\"", ts));
    Scene s = io::read_scene(m.path);
    ASSERT_EQ(s.elements.size(), 1u);
    EXPECT_EQ(s.elements[0].rect, (Rect{6, 6, 4, 4}));
}

TEST(Tiled, InfiniteMapChunks) {
    TempMap m("inf.tmx", map_xml("<layer name=\"ground\" width=\"0\" height=\"0\"><data encoding=\"csv\">"
                                 "<chunk x=\"-2\" y=\"0\" width=\"2\" height=\"1\">1,0</chunk>"
                                 "<chunk x=\"4\" y=\"1\" width=\"2\" height=\"1\">0,2</chunk></data></layer>",
                                 "orientation=\"orthogonal\" infinite=\"1\" width=\"30\" height=\"20\""));
    Scene s = io::read_scene(m.path);
    ASSERT_EQ(s.elements.size(), 2u);
    expect_element(s, 0, "tiles", {1, 1, 4, 4}, {1, 0, 0, 1, -8, 0});
    expect_element(s, 1, "tiles", {6, 1, 4, 4}, {1, 0, 0, 1, 20, 4});
    // The viewport of an infinite map is what it draws.
    EXPECT_EQ(s.viewport.x, -8);
    EXPECT_EQ(s.viewport.y, 0);
    EXPECT_EQ(s.viewport.width, 32);
    EXPECT_EQ(s.viewport.height, 8);
}

TEST(Tiled, TransColourKeyIsAppliedAtDecodeAndWritesNothing) {
    TempMap m("trans.tmx", map_xml(layer_xml("<data encoding=\"csv\">1,0,0,0,0,0</data>"),
                                   "orientation=\"orthogonal\" width=\"3\" height=\"2\"", tileset_xml(" trans=\"ff00ff\"")));
    // Loading writes nothing (issue 11: not even a keyed copy in a cache).
    std::string cache = (m.dir / "cache").string();
    const char* old = std::getenv("XDG_CACHE_HOME");
    std::string saved = old ? old : "";
    ::setenv("XDG_CACHE_HOME", cache.c_str(), 1);
    Scene s = io::read_scene(m.path);
    if (old) ::setenv("XDG_CACHE_HOME", saved.c_str(), 1);
    else ::unsetenv("XDG_CACHE_HOME");
    EXPECT_FALSE(std::filesystem::exists(cache));
    ASSERT_EQ(s.images.size(), 1u);
    ASSERT_TRUE(s.images[0].has_trans);
    EXPECT_EQ(s.images[0].trans, 0xff00ffu);
    Image keyed = io::read_scene_image(s.images[0]);
    ASSERT_EQ(keyed.width, 12);
    EXPECT_EQ(keyed.view().alpha(0, 0), 0);   // magenta gutter
    EXPECT_EQ(keyed.view().alpha(1, 1), 0);   // magenta texel inside tile 1
    EXPECT_EQ(keyed.view().alpha(2, 1), 255); // red
    EXPECT_EQ(keyed.view().alpha(6, 6), 128); // half-transparent yellow keeps its alpha
    // The file itself is untouched: a plain decode keeps magenta opaque.
    EXPECT_EQ(io::read_png(s.images[0].path).view().alpha(0, 0), 255);
    // Read through ImageFiles (as the pipeline loads), the key is applied
    // to the bytes the loader kept.
    io::ImageFiles files;
    io::LoadOptions options;
    options.image_files = &files;
    const Scene kept = io::read_scene(m.path, options);
    ASSERT_NE(files.find(kept.images[0].path), nullptr);
    EXPECT_EQ(io::read_scene_image(kept.images[0], &files).rgba, keyed.rgba);
}

TEST(Tiled, ObjectTemplates) {
    Scene s = io::read_scene(data("template.tmx"));
    ASSERT_EQ(s.elements.size(), 2u);
    // Template gid 2 of its tiles.tsx (firstgid 1) is map gid 6; the
    // instance overrides the height (8) and keeps the template's width (8).
    expect_element(s, 0, "tiles", {6, 1, 4, 4}, {2, 0, 0, 2, 4, 0});
    // An instance's own gid counts in the map's tilesets.
    expect_element(s, 1, "tiles", {1, 1, 4, 4}, {1, 0, 0, 1, 0, 12});
}

TEST(Tiled, IsometricTileObject) {
    // Object pixel coordinates count tile heights on both axes; the default
    // alignment on isometric maps is bottom centre.
    TempMap m("isoobj.tmx", "<map orientation=\"isometric\" width=\"2\" height=\"2\" tilewidth=\"8\" tileheight=\"4\">" + tileset_xml() +
                                "<objectgroup name=\"o\"><object id=\"1\" gid=\"1\" x=\"4\" y=\"4\"/></objectgroup></map>");
    Scene s = io::read_scene(m.path);
    ASSERT_EQ(s.elements.size(), 1u);
    expect_element(s, 0, "tiles", {1, 1, 4, 4}, {1, 0, 0, 1, 6, 0});
}

TEST(Tiled, SceneJsonRoundTrip) {
    // What import writes, read_scene reads back as the same scene.
    for (const char* name : {"csv.tmx", "objects.tmx", "iso.tmx", "tall.tmx"}) {
        Scene s = io::read_scene(data(name));
        TempMap m(std::string(name) + ".json", "");
        io::write_scene_json(m.path, s);
        Scene back = io::read_scene(m.path);
        ASSERT_EQ(back.elements.size(), s.elements.size()) << name;
        ASSERT_EQ(back.images.size(), s.images.size()) << name;
        EXPECT_EQ(back.viewport.width, s.viewport.width);
        EXPECT_EQ(back.viewport.height, s.viewport.height);
        for (std::size_t i = 0; i < s.images.size(); ++i) {
            EXPECT_EQ(back.images[i].id, s.images[i].id);
            EXPECT_TRUE(fs::equivalent(back.images[i].path, s.images[i].path)) << back.images[i].path;
        }
        for (std::size_t i = 0; i < s.elements.size(); ++i) {
            const Element &a = s.elements[i], &b = back.elements[i];
            EXPECT_EQ(back.images[std::size_t(b.image)].id, s.images[std::size_t(a.image)].id);
            EXPECT_EQ(a.rect, b.rect);
            EXPECT_EQ(a.transform, b.transform) << name << " element " << i;
            EXPECT_EQ(a.color, b.color) << name << " element " << i;
            EXPECT_EQ(a.blend, b.blend);
        }
    }
}

TEST(Tiled, StaggeredDrawsInScreenRasterOrder) {
    // staggeraxis y, odd rows shifted right by half a tile; rows 2 apart.
    TempMap m("stag.tmx", "<map orientation=\"staggered\" staggeraxis=\"y\" staggerindex=\"odd\" width=\"2\" height=\"2\" "
                          "tilewidth=\"8\" tileheight=\"4\">" + tileset_xml() +
                          "<layer name=\"g\" width=\"2\" height=\"2\"><data encoding=\"csv\">1,2,3,4</data></layer></map>");
    Scene s = io::read_scene(m.path);
    EXPECT_EQ(s.viewport.width, 20);
    EXPECT_EQ(s.viewport.height, 6);
    ASSERT_EQ(s.elements.size(), 4u);
    expect_element(s, 0, "tiles", {1, 1, 4, 4}, {1, 0, 0, 1, 0, 0});
    expect_element(s, 1, "tiles", {6, 1, 4, 4}, {1, 0, 0, 1, 8, 0});
    expect_element(s, 2, "tiles", {1, 6, 4, 4}, {1, 0, 0, 1, 4, 2});
    expect_element(s, 3, "tiles", {6, 6, 4, 4}, {1, 0, 0, 1, 12, 2});
}

TEST(Tiled, HexagonalRotationFlags) {
    // On hexagonal maps the anti-diagonal bit turns a tile 60 degrees and
    // bit 28 120 degrees clockwise about its centre: together, 180.
    TempMap m("hex.tmx", "<map orientation=\"hexagonal\" hexsidelength=\"2\" staggeraxis=\"x\" staggerindex=\"odd\" width=\"2\" "
                         "height=\"1\" tilewidth=\"4\" tileheight=\"4\">" + tileset_xml() +
                         "<layer name=\"g\" width=\"2\" height=\"1\"><data encoding=\"csv\">536870913,805306369</data></layer></map>");
    Scene s = io::read_scene(m.path);
    ASSERT_EQ(s.elements.size(), 2u);
    const auto& t60 = s.elements[0].transform;
    EXPECT_NEAR(t60[0], 0.5, 1e-12);
    EXPECT_NEAR(t60[1], std::sqrt(3.0) / 2, 1e-12);
    Vec2 centre = apply(t60, {2, 2});
    EXPECT_NEAR(centre.x, 2, 1e-12);
    EXPECT_NEAR(centre.y, 2, 1e-12);
    // Column 1 is staggered down by half a row (2); 180 degrees is exact.
    expect_element(s, 1, "tiles", {1, 1, 4, 4}, {-1, 0, 0, -1, 3 + 4, 2 + 4});
}

TEST(Tiled, TileRenderSizeGridScalesTiles) {
    // tilerendersize="grid": a 4x8 tile stretched to the 4x4 cell.
    std::string ts = "<tileset firstgid=\"1\" name=\"tall\" tilewidth=\"4\" tileheight=\"8\" tilerendersize=\"grid\"><image source=\"" +
                     data("tall.png") + "\"/></tileset>";
    TempMap m("grid.tmx", map_xml(layer_xml("<data encoding=\"csv\">0,1,0,0,0,0</data>"), "orientation=\"orthogonal\" width=\"3\" height=\"2\"", ts));
    Scene s = io::read_scene(m.path);
    ASSERT_EQ(s.elements.size(), 1u);
    expect_element(s, 0, "tall", {0, 0, 4, 8}, {1, 0, 0, 0.5, 4, 0});
}

TEST(Tiled, ImageLayer) {
    TempMap m("img.tmx", map_xml("<imagelayer name=\"sky\" offsetx=\"2\" offsety=\"1\" opacity=\"0.25\"><image source=\"" +
                                 data("b.png") + "\"/></imagelayer>"));
    Scene s = io::read_scene(m.path);
    ASSERT_EQ(s.elements.size(), 1u);
    expect_element(s, 0, "b", {0, 0, 6, 2}, {1, 0, 0, 1, 2, 1}, {1, 1, 1, 0.25f});
}

TEST(Tiled, SceneJsonText) {
    Scene s = io::read_scene(data("csv.tmx"));
    std::string out = (fs::path(data("csv.tmx")).parent_path() / "out.json").string();
    std::string text = io::scene_to_json_text(s, out);
    EXPECT_NE(text.find("{\"id\":\"tiles\",\"path\":\"tiles.png\"}"), std::string::npos) << text;
    EXPECT_NE(text.find("{\"image\":\"tiles\",\"rect\":[6,1,4,4],\"transform\":[-1,0,0,1,8,0],\"color\":[1,1,1,1],\"blend\":\"alpha\"}"),
              std::string::npos)
        << text;
    EXPECT_NE(text.find("\"viewport\": {\"x\":0,\"y\":0,\"width\":12,\"height\":8}"), std::string::npos) << text;
    EXPECT_EQ(text, io::scene_to_json_text(s, out)); // deterministic
}

// ---- Errors: one line, naming the file and the place.

TEST(TiledErrors, BadInputNamesFileAndLayer) {
    struct Case {
        const char* name;
        std::string body;
        std::string expect;
    } cases[] = {
        {"bad_base64", layer_xml("<data encoding=\"base64\">AAA*AAAA</data>"), "layer 'ground': bad base64 data"},
        {"bad_csv", layer_xml("<data encoding=\"csv\">1,x,0,0,0,0</data>"), "layer 'ground': bad CSV data"},
        {"short_csv", layer_xml("<data encoding=\"csv\">1,2</data>"), "layer 'ground': CSV data has 2 cells, expected 6"},
        {"short_base64", layer_xml("<data encoding=\"base64\">AQAAAA==</data>"), "layer 'ground': data has 4 bytes, expected 24"},
        {"bad_zlib", layer_xml("<data encoding=\"base64\" compression=\"zlib\">AQAAAA==</data>"), "layer 'ground': corrupt compressed data"},
        {"zstd", layer_xml("<data encoding=\"base64\" compression=\"zstd\">AQAAAA==</data>"), "layer 'ground': corrupt zstd data"},
        {"lzma", layer_xml("<data encoding=\"base64\" compression=\"lzma\">AQAAAA==</data>"), "layer 'ground': unsupported compression 'lzma'"},
        {"encoding", layer_xml("<data encoding=\"hex\">00</data>"), "layer 'ground': unsupported encoding 'hex'"},
        {"gid_range", layer_xml("<data encoding=\"csv\">1,99,0,0,0,0</data>"), "layer 'ground': gid 99 is out of range of tileset 'tiles'"},
        {"template", "<objectgroup name=\"things\"><object id=\"7\" template=\"t.tx\" x=\"0\" y=\"0\"/></objectgroup>",
         "object layer 'things': object 7: template 't.tx' not found"},
    };
    for (const Case& c : cases) {
        TempMap m(std::string(c.name) + ".tmx", map_xml(c.body));
        std::string error = load_error(m.path);
        EXPECT_EQ(error.rfind(m.path + ": ", 0), 0u) << c.name << ": " << error;
        EXPECT_NE(error.find(c.expect), std::string::npos) << c.name << ": " << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << c.name << ": " << error;
    }
}

TEST(TiledErrors, MissingFilesAndUnsupportedMaps) {
    {
        TempMap m("no_tsx.tmx", map_xml("", "orientation=\"orthogonal\" width=\"3\" height=\"2\"", "<tileset firstgid=\"1\" source=\"nope.tsx\"/>"));
        EXPECT_NE(load_error(m.path).find("nope.tsx: cannot open"), std::string::npos) << load_error(m.path);
    }
    {
        TempMap m("no_png.tmx", map_xml("", "orientation=\"orthogonal\" width=\"3\" height=\"2\"",
                                        "<tileset firstgid=\"1\" name=\"t\" tilewidth=\"4\" tileheight=\"4\"><image source=\"nope.png\"/></tileset>"));
        EXPECT_NE(load_error(m.path).find("tileset 't': image 'nope.png' not found"), std::string::npos) << load_error(m.path);
    }
    {
        TempMap m("oblique.tmx", map_xml("", "orientation=\"oblique\" width=\"3\" height=\"2\""));
        EXPECT_NE(load_error(m.path).find("oblique maps are not supported"), std::string::npos) << load_error(m.path);
    }
    {
        TempMap m("no_gid.tmx", map_xml(layer_xml("<data encoding=\"csv\">1,0,0,0,0,0</data>"), "orientation=\"orthogonal\" width=\"3\" height=\"2\"", ""));
        EXPECT_NE(load_error(m.path).find("layer 'ground': gid 1 has no tileset"), std::string::npos) << load_error(m.path);
    }
    {
        TempMap m("junk.tmx", "<map orientation=");
        EXPECT_NE(load_error(m.path).find("XML error"), std::string::npos) << load_error(m.path);
    }
    {
        TempMap m("huge.tmx", map_xml("<layer name=\"ground\" width=\"100000\" height=\"100000\"><data encoding=\"csv\">1</data></layer>",
                                      "orientation=\"orthogonal\" width=\"100000\" height=\"100000\""));
        EXPECT_NE(load_error(m.path).find("layer 'ground': layer size 100000x100000 is outside"), std::string::npos) << load_error(m.path);
    }
}

// Corrupted maps never crash or hang: each byte-level mutation of a valid
// map loads or throws depthcull::Error.
TEST(TiledErrors, MutatedMapsFailCleanly) {
    std::mt19937 rng(12345);
    for (const char* name : {"csv.tmx", "zlib.tmx", "gzip.tmx", "objects.tmx", "iso.tmx"}) {
        std::string original = io::read_file(data(name));
        // Image sources relative to the test data, from wherever the copy lives.
        std::string text = original;
        for (const char* png : {"tiles.png", "a.png", "b.png"}) {
            std::string from = "source=\"" + std::string(png) + "\"", to = "source=\"" + data(png) + "\"";
            for (std::size_t at; (at = text.find(from)) != std::string::npos;) text.replace(at, from.size(), to);
        }
        for (std::size_t at; (at = text.find("source=\"tiles.tsx\"")) != std::string::npos;)
            text.replace(at, 19, "source=\"" + data("tiles.tsx") + "\"");
        TempMap m(std::string("m_") + name, "");
        for (int round = 0; round < 40; ++round) {
            std::string mutated = text;
            int edits = 1 + int(rng() % 4);
            for (int k = 0; k < edits; ++k) {
                std::size_t at = rng() % mutated.size();
                switch (rng() % 3) {
                case 0: mutated[at] = char(rng() % 256); break;
                case 1: mutated.erase(at, 1 + rng() % 8); break;
                default: mutated.insert(at, 1, "0123456789,=<>\"-x"[rng() % 17]); break;
                }
                if (mutated.empty()) mutated = "x";
            }
            std::ofstream(m.path, std::ios::binary | std::ios::trunc) << mutated;
            try {
                Scene s = io::read_scene(m.path);
                EXPECT_LE(s.elements.size(), 64u) << name << " round " << round;
            } catch (const depthcull::Error& e) {
                EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
            }
        }
    }
}
