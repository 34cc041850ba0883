// Tiled's other formats (issue 15): JSON maps and tilesets written by Tiled
// 1.8.2 (tests/data/tiled/*.tmj, *.tsj), zstd layer data, repeating image
// layers, the background colour, parallax at the chosen camera, warnings
// and --strict; images by content (PNG, JPEG, WebP).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>

#include "depthcull/io.h"
#include "test_scene_json_helpers.h"
#include "depthcull/pipeline.h"
#include "testing/corpus.h"
#include "tiled_expect.h"

using namespace depthcull;
namespace fs = std::filesystem;

namespace {

using test::T;
using test::data;
using test::expect_element;
using test::expect_flips_map;

// A scratch directory named after the running test.
struct TempDir : test::SceneDir {
    TempDir() : SceneDir("tiled_formats_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())) {}
    const fs::path& dir = root;
};

std::string error_of(const std::function<void()>& fn) {
    try {
        fn();
    } catch (const depthcull::Error& e) {
        return e.what();
    }
    return "(no error)";
}

// A 3x2 map of 4x4 cells (viewport 12x8) with `body` after the tiles tileset.
std::string map_xml(const std::string& body, const std::string& map_attrs = "", const std::string& tileset_body = "") {
    return "<?xml version=\"1.0\"?><map version=\"1.10\" orientation=\"orthogonal\" width=\"3\" height=\"2\" tilewidth=\"4\" tileheight=\"4\" " +
           map_attrs + "><tileset firstgid=\"1\" name=\"tiles\" tilewidth=\"4\" tileheight=\"4\" spacing=\"1\" margin=\"1\"><image source=\"" +
           data("tiles.png") + "\"/>" + tileset_body + "</tileset>" + body + "</map>";
}

} // namespace

// ---- JSON maps and tilesets, as Tiled 1.8.2 exported them from csv.tmx

TEST(TiledJson, MapTmj) { expect_flips_map(io::read_scene(data("csv.tmj"))); }
TEST(TiledJson, MapJsonToldByContent) { expect_flips_map(io::read_scene(data("flips_map.json"))); }
TEST(TiledJson, TmxWithJsonTileset) { expect_flips_map(io::read_scene(data("external_json.tmx"))); }
TEST(TiledJson, TmjWithJsonTileset) { expect_flips_map(io::read_scene(data("external_json.tmj"))); }

TEST(TiledJson, ZstdLayerData) {
    expect_flips_map(io::read_scene(data("zstd.tmx")));  // made with the zstd tool
    expect_flips_map(io::read_scene(data("zstd.tmj")));  // re-compressed by Tiled 1.8.2
}

// pugixml's as_int / as_double read the leading digits and give 0 for
// junk: "width": 1e300 became 1 (a tile dropped), opacity="x" hid the
// layer, gid="abc" emptied the cell. Numbers are read whole now; a whole
// number written 2.0 is still the integer Tiled's reader takes it for.
TEST(TiledJson, NumbersAreReadWholeOrRefused) {
    TempDir t;
    auto tmj = [&](const std::string& name, const std::string& width) {
        return t.write(name, R"({"width":)" + width + R"(,"height":1,"tilewidth":3,"tileheight":5,"orientation":"orthogonal",
            "tilesets":[{"firstgid":1,"name":"c","tilewidth":3,"tileheight":5,"tiles":[{"id":0,"image":")" + data("a.png") + R"("}]}],
            "layers":[{"type":"tilelayer","name":"l","width":)" + width + R"(,"height":1,"data":[1)" + (width == "1" ? "" : ",1") + "]}]}");
    };
    EXPECT_EQ(io::read_scene(tmj("two.tmj", "2.0")).elements.size(), 2u);
    const std::string huge = tmj("huge.tmj", "1e300");
    EXPECT_EQ(error_of([&] { io::read_scene(huge); }), huge + ": attribute width=\"1e+300\" is not an integer");
    const std::string half = tmj("half.tmj", "2.5");
    EXPECT_EQ(error_of([&] { io::read_scene(half); }), half + ": attribute width=\"2.5\" is not an integer");

    const std::string opacity = t.write("opacity.tmx", map_xml("<layer name=\"g\" width=\"3\" height=\"2\" opacity=\"x\"><data encoding=\"csv\">1,0,0,0,0,0</data></layer>"));
    EXPECT_EQ(error_of([&] { io::read_scene(opacity); }), opacity + ": layer 'g': attribute opacity=\"x\" is not a number");
    const std::string cell = t.write("cell.tmx", map_xml("<layer name=\"g\" width=\"3\" height=\"2\"><data><tile gid=\"abc\"/></data></layer>"));
    EXPECT_EQ(error_of([&] { io::read_scene(cell); }), cell + ": layer 'g': attribute gid=\"abc\" is not a tile gid (0..4294967295)");
    const std::string object = t.write("object.tmx", map_xml("<objectgroup name=\"o\"><object id=\"1\" gid=\"1\" x=\"12abc\" y=\"4\"/></objectgroup>"));
    EXPECT_NE(error_of([&] { io::read_scene(object); }).find("attribute x=\"12abc\" is not a number"), std::string::npos);

    // A template's tileset firstgid is read whole too, and kept to 1..2^28-1:
    // a negative one would shift the object's gid onto another tile.
    for (const char* name : {"template.tmx", "tiles.tsx", "tiles.png"}) std::filesystem::copy_file(data(name), t.dir / name);
    const std::string tx = io::read_file(data("tile.tx"));
    std::string negative = tx;
    negative.replace(negative.find("firstgid=\"1\""), 12, "firstgid=\"-5\"");
    t.write("tile.tx", negative);
    const std::string templated = (t.dir / "template.tmx").string();
    EXPECT_NE(error_of([&] { io::read_scene(templated); }).find("tile.tx: template's tileset firstgid out of range 1..268435455"), std::string::npos)
        << error_of([&] { io::read_scene(templated); });
}

// Some editors save JSON with a UTF-8 byte order mark: such a map was told
// from XML by its first byte and refused as an "XML error".
TEST(TiledJson, AByteOrderMarkIsSkipped) {
    TempDir t;
    const std::string text = io::read_file(data("csv.tmj"));
    std::filesystem::copy_file(data("tiles.png"), t.dir / "tiles.png");
    expect_flips_map(io::read_scene(t.write("bom.tmj", "\xEF\xBB\xBF" + text)));
}

TEST(TiledJson, OldTilesObjectAndBadJson) {
    TempDir t;
    // Tiled before 1.2 wrote "tiles" as an object keyed by id.
    std::string map = t.write("old.tmj", R"({"width":1,"height":1,"tilewidth":3,"tileheight":5,"orientation":"orthogonal",
        "tilesets":[{"firstgid":1,"name":"c","tilewidth":3,"tileheight":5,"tiles":{"0":{"image":")" + data("a.png") + R"("}}}],
        "layers":[{"type":"tilelayer","name":"l","width":1,"height":1,"data":[1]}]})");
    Scene s = io::read_scene(map);
    ASSERT_EQ(s.elements.size(), 1u);
    expect_element(s, 0, "a", {0, 0, 3, 5}, {1, 0, 0, 1, 0, 0});
    std::string bad = t.write("bad.tmj", R"({"width":1,"height":1,"tilewidth":3,"tileheight":5,"layers":[{"type":"pie"}]})");
    EXPECT_EQ(error_of([&] { io::read_scene(bad); }), bad + ": layer '': unknown layer type 'pie'");
    std::string broken = t.write("broken.tmj", "{\"layers\": [");
    EXPECT_NE(error_of([&] { io::read_scene(broken); }).find(broken + ": not valid JSON at line 1, column "), std::string::npos);
    std::string gid = t.write("gid.tmj", R"({"width":1,"height":1,"tilewidth":3,"tileheight":5,"layers":[{"type":"tilelayer","width":1,"height":1,"data":[-1]}]})");
    EXPECT_EQ(error_of([&] { io::read_scene(gid); }), gid + ": layer '': \"data\" holds a value that is not a gid (a whole number 0..4294967295)");
}

TEST(TiledJson, CorruptZstdIsOneLine) {
    TempDir t;
    std::string map = t.write("z.tmx", map_xml("<layer name=\"g\" width=\"3\" height=\"2\"><data encoding=\"base64\" compression=\"zstd\">AAAAAAAA</data></layer>"));
    std::string e = error_of([&] { io::read_scene(map); });
    EXPECT_EQ(e.rfind(map + ": layer 'g': corrupt zstd data (", 0), 0u) << e;
}

// ---- image layers, background, parallax

TEST(TiledLayers, RepeatingImageLayerTilesTheCamera) {
    TempDir t;
    // a.png is 3x5; the camera 0,0,12,8; offset x 1: copies at x = -2, 1, 4, 7, 10.
    std::string map = t.write("r.tmx", map_xml("<imagelayer name=\"sky\" offsetx=\"1\" repeatx=\"1\"><image source=\"" + data("a.png") + "\"/></imagelayer>"));
    Scene s = io::read_scene(map);
    ASSERT_EQ(s.elements.size(), 5u);
    for (int k = 0; k < 5; ++k) expect_element(s, std::size_t(k), "a", {0, 0, 3, 5}, {1, 0, 0, 1, -2.0 + 3 * k, 0});
    std::string both = t.write("rb.tmx", map_xml("<imagelayer name=\"sky\" repeatx=\"1\" repeaty=\"1\"><image source=\"" + data("a.png") + "\"/></imagelayer>"));
    s = io::read_scene(both);
    ASSERT_EQ(s.elements.size(), 8u); // 4 columns (0..11) x 2 rows (0..9)
    expect_element(s, 0, "a", {0, 0, 3, 5}, {1, 0, 0, 1, 0, 0});
    expect_element(s, 7, "a", {0, 0, 3, 5}, {1, 0, 0, 1, 9, 5});
}

TEST(TiledLayers, BackgroundColourIsAnOpaqueFirstElement) {
    TempDir t;
    std::string map = t.write("bg.tmx", map_xml("<layer name=\"g\" width=\"3\" height=\"2\"><data encoding=\"csv\">1,0,0,0,0,0</data></layer>",
                                                "backgroundcolor=\"#102030\""));
    Scene s = io::read_scene(map);
    ASSERT_EQ(s.elements.size(), 2u);
    expect_element(s, 0, "background", {0, 0, kFillImageSide, kFillImageSide}, {12.0 / kFillImageSide, 0, 0, 8.0 / kFillImageSide, 0, 0});
    const SceneImage& bg = s.images.at(std::size_t(s.elements[0].image));
    EXPECT_TRUE(bg.has_fill);
    EXPECT_EQ(bg.fill, 0x102030u);
    EXPECT_TRUE(bg.path.empty());
    Image pixels = io::read_scene_image(bg);
    ASSERT_EQ(pixels.width, kFillImageSide);
    EXPECT_EQ(pixels.rgba[0], 0x10);
    EXPECT_EQ(pixels.rgba[1], 0x20);
    EXPECT_EQ(pixels.rgba[2], 0x30);
    EXPECT_EQ(pixels.rgba[3], 255);
    // Our scene JSON carries it ("fill", no path) and reads it back.
    std::string text = io::scene_to_json_text(s, (t.dir / "scene.json").string());
    EXPECT_NE(text.find("{\"id\":\"background\",\"fill\":\"102030\"}"), std::string::npos) << text;
    std::string scene = t.write("scene.json", text);
    Scene back = io::read_scene(scene);
    ASSERT_EQ(back.images.size(), s.images.size());
    EXPECT_TRUE(back.images[std::size_t(back.elements[0].image)].has_fill);
    EXPECT_EQ(back.images[std::size_t(back.elements[0].image)].fill, 0x102030u);
    // ARGB: the alpha is the element's.
    std::string argb = t.write("argb.tmx", map_xml("", "backgroundcolor=\"#80102030\""));
    s = io::read_scene(argb);
    ASSERT_EQ(s.elements.size(), 1u);
    EXPECT_FLOAT_EQ(s.elements[0].color[3], float(0x80) / 255.0f);
}

TEST(TiledLayers, ParallaxAtTheCameraWithANote) {
    TempDir t;
    std::string map = t.write("p.tmx", map_xml("<group name=\"far\" parallaxx=\"0\"><imagelayer name=\"hills\" parallaxy=\"0.25\" offsetx=\"2\">"
                                               "<image source=\"" + data("a.png") + "\"/></imagelayer></group>", "parallaxoriginx=\"4\""));
    io::LoadOptions options;
    options.has_viewport = true;
    options.viewport = {50, 20, 12, 8}; // centre 56, 24
    std::vector<std::string> notes, warnings;
    options.note = [&](const std::string& line) { notes.push_back(line); };
    options.warning = [&](const std::string& line) { warnings.push_back(line); };
    options.strict = true; // a note is not a warning
    Scene s = io::read_scene(map, options);
    ASSERT_EQ(s.elements.size(), 1u);
    // Factors: x 0 (the group's, fixed to the camera), y 0.25.
    // x: 2 + (1 - 0) * (56 - 4) = 54; y: (1 - 0.25) * (24 - 0) = 18.
    expect_element(s, 0, "a", {0, 0, 3, 5}, {1, 0, 0, 1, 54, 18});
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_EQ(notes[0], map + ": image layer 'hills': parallax layer placed for the camera centred at 56,24: meshes are valid for this camera only");
    EXPECT_TRUE(warnings.empty());
}

TEST(TiledLayers, UnsupportedFeaturesWarnOnceOrFailWithStrict) {
    TempDir t;
    std::string map = t.write("w.tmx", map_xml("<layer name=\"g\" width=\"3\" height=\"2\"><data encoding=\"csv\">1,1,0,0,0,0</data></layer>"
                                               "<objectgroup name=\"labels\"><object id=\"7\" x=\"1\" y=\"1\"><text>hi</text></object></objectgroup>",
                                               "", "<tile id=\"0\"><animation><frame tileid=\"1\" duration=\"100\"/></animation></tile>"));
    io::LoadOptions options;
    std::vector<std::string> warnings;
    options.warning = [&](const std::string& line) { warnings.push_back(line); };
    Scene s = io::read_scene(map, options);
    EXPECT_EQ(s.elements.size(), 2u);
    EXPECT_EQ(s.animations.size(), 1u); // animated tiles are recorded, not warned about
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], map + ": object layer 'labels': text objects are not drawn");
    options.strict = true;
    EXPECT_EQ(error_of([&] { io::read_scene(map, options); }), map + ": object layer 'labels': text objects are not drawn (--strict)");
}

// The Mana World's water tileset animates two tiles through ids past its
// image; nine maps that never show them load in Tiled and the game. Such
// frames are left out, with a warning only where the tile is shown.
TEST(TiledAnimation, FramesNamingNoTileAreLeftOutAndWarnedOnlyWhereShown) {
    TempDir t;
    const std::string tiles = "<tile id=\"1\"><animation><frame tileid=\"0\" duration=\"100\"/><frame tileid=\"190\" duration=\"100\"/>"
                              "<frame tileid=\"191\" duration=\"100\"/></animation></tile>"
                              "<tile id=\"2\"><animation><frame tileid=\"500\" duration=\"100\"/></animation></tile>";
    auto layer = [](const std::string& cells) {
        return "<layer name=\"g\" width=\"3\" height=\"2\"><data encoding=\"csv\">" + cells + "</data></layer>";
    };
    io::LoadOptions options;
    std::vector<std::string> warnings;
    options.warning = [&](const std::string& line) { warnings.push_back(line); };
    const std::string unused = t.write("unused.tmx", map_xml(layer("1,1,4,0,0,0"), "", tiles));
    Scene s = io::read_scene(unused, options);
    EXPECT_EQ(s.elements.size(), 3u);
    EXPECT_TRUE(s.animations.empty());
    EXPECT_TRUE(warnings.empty());

    const std::string shown = t.write("shown.tmx", map_xml(layer("2,2,3,0,0,0"), "", tiles));
    s = io::read_scene(shown, options);
    ASSERT_EQ(s.elements.size(), 3u);
    ASSERT_EQ(s.animations.size(), 1u); // tile 1: its one frame that names a tile
    ASSERT_EQ(s.animations[0].frames.size(), 1u);
    EXPECT_EQ(s.elements[0].animation, 0);
    EXPECT_EQ(s.elements[2].animation, -1); // tile 2: no frame left, drawn still
    ASSERT_EQ(warnings.size(), 2u);
    EXPECT_EQ(warnings[0].rfind(shown + ": layer 'g': animated tile 1 of tileset 'tiles': frame names no tile (190, 191; the tileset has ", 0), 0u)
        << warnings[0];
    EXPECT_NE(warnings[0].find(" tiles): those frames are left out"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[1].find("animated tile 2 of tileset 'tiles': frame names no tile (500; the tileset has "), std::string::npos) << warnings[1];
    options.strict = true;
    EXPECT_NE(error_of([&] { io::read_scene(shown, options); }).find("those frames are left out (--strict)"), std::string::npos);
    EXPECT_NO_THROW(io::read_scene(unused, options));

    // The Mana World's animation-frameN properties: not read, warned where shown.
    options.strict = false;
    warnings.clear();
    const std::string mana = t.write("mana.tmx", map_xml(layer("4,1,0,0,0,0"), "",
                                                         "<tile id=\"3\"><properties><property name=\"animation-frame0\" value=\"1\"/>"
                                                         "<property name=\"animation-delay0\" value=\"10\"/></properties></tile>"));
    s = io::read_scene(mana, options);
    EXPECT_EQ(s.elements.size(), 2u);
    EXPECT_TRUE(s.animations.empty());
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], mana + ": layer 'g': animated tile 3 of tileset 'tiles': animation-frameN / animation-delayN properties (The Mana "
                                  "World's form) are not read: drawn as its still tile");
}

// ---- images by content

TEST(ImageFormats, WebpLosslessEqualsThePng) {
    Image png = io::read_png(data("a.png"));
    Image webp = io::read_image(data("a_lossless.webp"));
    EXPECT_EQ(webp.width, png.width);
    EXPECT_EQ(webp.height, png.height);
    EXPECT_EQ(webp.rgba, png.rgba);
}

TEST(ImageFormats, JpegAndOpaqueWebpAreFullyOpaque) {
    for (const char* name : {"opaque.jpg", "opaque.webp"}) {
        Image image = io::read_image(data(name));
        ASSERT_EQ(image.width, 4) << name;
        ASSERT_EQ(image.height, 3) << name;
        for (std::size_t i = 3; i < image.rgba.size(); i += 4) EXPECT_EQ(image.rgba[i], 255) << name;
        EXPECT_GT(image.rgba[0], 200) << name;                      // red on the left
        EXPECT_GT(image.rgba[std::size_t(3 * 4 + 2)], 200) << name; // blue on the right
        // The analysis exploits it: the whole image is one opaque polygon.
        ImageAnalysis a = analyze_image(image.view(), image.view().bounds(), {});
        EXPECT_EQ(a.stats.opaque_texels, 12) << name;
    }
}

TEST(ImageFormats, ToldByContentNotName) {
    TempDir t;
    std::string bytes = io::read_file(data("a.png"));
    std::string misnamed = t.write("really_a_png.jpg", bytes);
    EXPECT_EQ(io::read_image(misnamed).rgba, io::read_png(data("a.png")).rgba);
    std::string junk = t.write("junk.png", "hello");
    EXPECT_EQ(error_of([&] { io::read_image(junk); }), junk + " is not a PNG, JPEG or WebP image");
    std::string cut = t.write("cut.jpg", io::read_file(data("opaque.jpg")).substr(0, 40));
    EXPECT_EQ(error_of([&] { io::read_image(cut); }).rfind(cut + ": corrupt JPEG (", 0), 0u);
    std::string webp = t.write("cut.webp", io::read_file(data("opaque.webp")).substr(0, 20));
    EXPECT_EQ(error_of([&] { io::read_image(webp); }).rfind(webp + ": corrupt WebP (", 0), 0u);
}

TEST(ImageFormats, TiledMapWithJpegTiles) {
    TempDir t;
    std::string map = t.write("j.tmx", "<map orientation=\"orthogonal\" width=\"1\" height=\"1\" tilewidth=\"4\" tileheight=\"3\">"
                                       "<tileset firstgid=\"1\" name=\"j\" tilewidth=\"4\" tileheight=\"3\"><image source=\"" + data("opaque.jpg") +
                                       "\"/></tileset><layer name=\"g\" width=\"1\" height=\"1\"><data encoding=\"csv\">1</data></layer></map>");
    Scene s = io::read_scene(map);
    ASSERT_EQ(s.images.size(), 1u);
    EXPECT_EQ(s.images[0].width, 4);
    EXPECT_EQ(s.images[0].height, 3);
}

TEST(TiledLayers, BackgroundFillTravelsInBothMeshForms) {
    std::vector<SceneImage> images(2);
    images[0] = {"tiles", data("tiles.png"), 12, 12};
    images[1].id = "background";
    images[1].has_fill = true;
    images[1].fill = 0x3b97d3;
    images[1].width = images[1].height = kFillImageSide;
    io::MeshesDocument document;
    document.images = images;
    document.meshes.viewport = {0, 0, 12, 8};
    std::string text = io::meshes_to_json(document, "");
    EXPECT_NE(text.find("{\"id\": \"background\", \"path\": \"\", \"width\": 16, \"height\": 16, \"fill\": \"3b97d3\"}"), std::string::npos) << text;
    for (const io::MeshesDocument& back : {io::meshes_from_json(text, "m.json"), io::meshes_from_binary(io::meshes_to_binary(document, ""), "m.bin")}) {
        ASSERT_EQ(back.images.size(), 2u);
        EXPECT_FALSE(back.images[0].has_fill);
        EXPECT_TRUE(back.images[1].has_fill);
        EXPECT_EQ(back.images[1].fill, 0x3b97d3u);
        EXPECT_TRUE(back.images[1].path.empty());
    }
}

// ---- animated tiles: every frame drawn correctly, the animation recorded

TEST(TiledAnimation, OneAnalysisCoversEveryFrame) {
    TempDir t;
    // Two 16x16 tiles: A opaque in columns 0..11, B in columns 4..15 (and a
    // translucent texel): the union is the whole tile, the intersection
    // columns 4..11.
    Image sheet;
    sheet.width = 32;
    sheet.height = 16;
    sheet.rgba.assign(32 * 16 * 4, 0);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            if (x < 12) sheet.rgba[std::size_t(y * 32 + x) * 4 + 3] = 255;
            if (x >= 4) sheet.rgba[std::size_t(y * 32 + 16 + x) * 4 + 3] = 255;
        }
    sheet.rgba[std::size_t(0 * 32 + 16 + 0) * 4 + 3] = 100; // B's top-left: translucent
    io::write_png((t.dir / "anim.png").string(), sheet.view());
    std::string map = t.write("a.tmx", "<map orientation=\"orthogonal\" width=\"1\" height=\"1\" tilewidth=\"16\" tileheight=\"16\">"
                                       "<tileset firstgid=\"1\" name=\"a\" tilewidth=\"16\" tileheight=\"16\"><image source=\"anim.png\"/>"
                                       "<tile id=\"0\"><animation><frame tileid=\"0\" duration=\"100\"/><frame tileid=\"1\" duration=\"250\"/></animation></tile>"
                                       "</tileset><layer name=\"g\" width=\"1\" height=\"1\"><data encoding=\"csv\">1</data></layer></map>");
    io::LoadOptions options;
    std::vector<std::string> warnings;
    options.warning = [&](const std::string& line) { warnings.push_back(line); };
    pipeline::PrepareOptions prepare;
    prepare.load = options;
    pipeline::PreparedScene p = pipeline::prepare_scene(map, prepare);
    EXPECT_TRUE(warnings.empty());
    const Scene& s = p.scene;
    ASSERT_EQ(s.animations.size(), 1u);
    ASSERT_EQ(s.animations[0].frames.size(), 2u);
    EXPECT_EQ(s.animations[0].frames[0].rect, (Rect{0, 0, 16, 16}));
    EXPECT_EQ(s.animations[0].frames[1].rect, (Rect{16, 0, 16, 16}));
    EXPECT_EQ(s.animations[0].frames[0].duration_ms, 100);
    EXPECT_EQ(s.animations[0].frames[1].duration_ms, 250);
    ASSERT_EQ(s.elements.size(), 1u);
    EXPECT_EQ(s.elements[0].animation, 0);
    const ImageAnalysis& a = *p.analysis.of(0);
    EXPECT_EQ(a.rect, (Rect{0, 0, 16, 16}));
    ASSERT_FALSE(a.opaque.empty());
    // Each frame, with the polygons moved onto its rect, keeps both guarantees.
    const ImageView image = p.view(0);
    for (const AnimationFrame& f : s.animations[0].frames) {
        auto moved = [&](std::vector<Polygon> polygons) {
            for (Polygon& poly : polygons)
                for (Vec2& v : poly) v = {v.x + f.rect.x, v.y + f.rect.y};
            return polygons;
        };
        EXPECT_EQ(count_uncontained_texels(image, f.rect, moved(a.boundary), Filter::nearest), 0) << f.rect.x;
        EXPECT_EQ(count_opaque_violations(image, f.rect, moved(a.opaque), Filter::nearest), 0) << f.rect.x;
    }
    for (const Polygon& poly : a.opaque)
        for (const Vec2& v : poly) {
            EXPECT_GE(v.x, 4.0);
            EXPECT_LE(v.x, 12.0);
        }
    // Frame 0 alone would have had opaque texels in columns 0..3: not here.
    ImageAnalysis alone = analyze_image(image, {0, 0, 16, 16}, {});
    EXPECT_GT(alone.stats.opaque_covered_texels, a.stats.opaque_covered_texels);

    // Recorded in our scene JSON (and read back) and in the meshes JSON.
    std::string text = io::scene_to_json_text(s, (t.dir / "s.json").string());
    EXPECT_NE(text.find("\"animation\":0"), std::string::npos) << text;
    EXPECT_NE(text.find("{\"frames\":[{\"image\":\"anim\",\"rect\":[0,0,16,16],\"duration\":100},{\"image\":\"anim\",\"rect\":[16,0,16,16],\"duration\":250}]}"),
              std::string::npos) << text;
    Scene back = io::read_scene(t.write("s.json", text));
    ASSERT_EQ(back.animations.size(), 1u);
    EXPECT_EQ(back.animations[0].frames[1].rect, (Rect{16, 0, 16, 16}));
    EXPECT_EQ(back.animations[0].frames[1].duration_ms, 250);
    EXPECT_EQ(back.elements[0].animation, 0);
    SceneMeshes meshes;
    ReconstructOptions spans;
    spans.element_spans = true; // the meshes JSON's "animated" runs
    reconstruct_scene(s, p.analysis, spans, &meshes);
    std::string mesh_text = io::meshes_to_json(io::meshes_document(s, meshes), "");
    auto doc = nlohmann::json::parse(mesh_text);
    ASSERT_EQ(doc["animations"].size(), 1u);
    EXPECT_EQ(doc["animations"][0]["frames"][1], nlohmann::json::parse(R"({"image": 0, "rect": [16, 0, 16, 16], "duration": 250})"));
    ASSERT_FALSE(doc["animated"].empty());
    std::size_t covered = 0;
    for (const auto& run : doc["animated"]) {
        EXPECT_EQ(run["animation"], 0);
        covered += run["vertex_count"].get<std::size_t>();
    }
    std::size_t total = 0;
    for (const auto& d : doc["draws"]) total += d["vertices"].size() / 9;
    EXPECT_EQ(covered, total); // the only element is animated
    // The readers still read it (unknown fields are ignored).
    EXPECT_EQ(io::meshes_from_json(mesh_text, "m.json").meshes.draws.size(), meshes.draws.size());
}

TEST(TiledAnimation, FramesOfDifferentSizesWarn) {
    TempDir t;
    std::string map = t.write("d.tmx", "<map orientation=\"orthogonal\" width=\"1\" height=\"1\" tilewidth=\"4\" tileheight=\"4\">"
                                       "<tileset firstgid=\"1\" name=\"c\" tilewidth=\"4\" tileheight=\"5\">"
                                       "<tile id=\"0\"><image source=\"" + data("a.png") + "\"/></tile>"
                                       "<tile id=\"1\"><image source=\"" + data("tiles.png") + "\"/></tile>"
                                       "<tile id=\"2\"><image source=\"" + data("a.png") + "\"/><animation><frame tileid=\"0\" duration=\"1\"/><frame tileid=\"1\" duration=\"1\"/></animation></tile>"
                                       "</tileset><layer name=\"g\" width=\"1\" height=\"1\"><data encoding=\"csv\">3</data></layer></map>");
    io::LoadOptions options;
    std::vector<std::string> warnings;
    options.warning = [&](const std::string& line) { warnings.push_back(line); };
    Scene s = io::read_scene(map, options);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], map + ": layer 'g': animated tile 2 of tileset 'c' has frames of different sizes: drawn at its first frame, not animated");
    EXPECT_EQ(s.elements.at(0).animation, -1);
}

TEST(TiledLayers, FillModePreserveAspectFitCentresTheScaledTile) {
    TempDir t;
    // a.png (3x5) as a tile in 4x4 grid cells: scale 0.8 -> 2.4 x 4, centred (0.8 in from the left).
    std::string map = t.write("f.tmx", "<map orientation=\"orthogonal\" width=\"2\" height=\"1\" tilewidth=\"4\" tileheight=\"4\">"
                                       "<tileset firstgid=\"1\" name=\"c\" tilewidth=\"3\" tileheight=\"5\" tilerendersize=\"grid\" fillmode=\"preserve-aspect-fit\">"
                                       "<tile id=\"0\"><image source=\"" + data("a.png") + "\"/></tile></tileset>"
                                       "<layer name=\"g\" width=\"2\" height=\"1\"><data encoding=\"csv\">0,1</data></layer></map>");
    Scene s = io::read_scene(map);
    ASSERT_EQ(s.elements.size(), 1u);
    expect_element(s, 0, "a", {0, 0, 3, 5}, {0.8, 0, 0, 0.8, 4 + (4 - 2.4) / 2, 0});
}

TEST(TiledJson, JsonTemplateInAJsonMap) {
    TempDir t;
    t.write("t.tj", R"({"type": "template", "tileset": {"firstgid": 1, "source": ")" + data("tiles.tsj") +
                        R"("}, "object": {"gid": 2, "width": 8, "height": 8}})");
    std::string map = t.write("m.tmj", R"({"type": "map", "orientation": "orthogonal", "width": 3, "height": 2, "tilewidth": 4, "tileheight": 4,
        "tilesets": [{"firstgid": 1, "source": ")" + data("tiles.tsj") + R"("}],
        "layers": [{"type": "objectgroup", "name": "things", "objects": [{"id": 1, "template": "t.tj", "x": 2, "y": 8}]}]})");
    Scene s = io::read_scene(map);
    ASSERT_EQ(s.elements.size(), 1u);
    // gid 2: tile (6,1); the template's 8x8 size scales it 2x; bottom-left at (2, 8).
    expect_element(s, 0, "tiles", {6, 1, 4, 4}, {2, 0, 0, 2, 2, 0});
}

TEST(TiledLayers, BlendModesWarn) {
    TempDir t;
    std::string map = t.write("m.tmx", map_xml("<layer name=\"g\" mode=\"multiply\" width=\"3\" height=\"2\"><data encoding=\"csv\">1,0,0,0,0,0</data></layer>"));
    io::LoadOptions options;
    std::vector<std::string> warnings;
    options.warning = [&](const std::string& line) { warnings.push_back(line); };
    io::read_scene(map, options);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], map + ": layer 'g': layer blend mode 'multiply' is drawn as normal");
}

// Mutated JSON maps, JSON tilesets and plists: a scene or one depthcull::Error
// line, never a crash or another exception.
TEST(TiledJson, MutatedFilesFailCleanly) {
    std::mt19937 rng(4242);
    TempDir t;
    fs::copy_file(data("tiles.png"), t.dir / "tiles.png");
    fs::copy_file(test::source_path("tests/data/atlas/packed/cocos2d-0.png"), t.dir / "cocos2d-0.png");
    struct Case {
        std::string file, name;
    } cases[] = {{data("csv.tmj"), "m.tmj"}, {data("zstd.tmj"), "z.tmj"}, {data("tiles.tsj"), "tiles.tsj"},
                 {test::source_path("tests/data/atlas/packed/cocos2d-0.plist"), "c.plist"}};
    // A map naming the (mutated) tileset.
    std::string tsx_map = t.write("uses_tsj.tmx", "<map orientation=\"orthogonal\" width=\"3\" height=\"2\" tilewidth=\"4\" tileheight=\"4\">"
                                                  "<tileset firstgid=\"1\" source=\"tiles.tsj\"/><layer name=\"g\" width=\"3\" height=\"2\">"
                                                  "<data encoding=\"csv\">1,2,3,4,0,0</data></layer></map>");
    for (const Case& c : cases) {
        std::string text = io::read_file(c.file);
        for (int round = 0; round < 60; ++round) {
            std::string mutated = text;
            int edits = 1 + int(rng() % 4);
            for (int k = 0; k < edits; ++k) {
                std::size_t at = rng() % mutated.size();
                switch (rng() % 3) {
                case 0: mutated[at] = char(rng() % 256); break;
                case 1: mutated.erase(at, 1 + rng() % 8); break;
                default: mutated.insert(at, 1, "0123456789,:{}[]\"-e."[rng() % 20]); break;
                }
                if (mutated.empty()) mutated = "x";
            }
            std::string path = t.write(c.name, mutated);
            try {
                if (c.name == "c.plist") io::read_atlas(path);
                else if (c.name == "tiles.tsj") io::read_scene(tsx_map);
                else io::read_scene(path);
            } catch (const depthcull::Error& e) {
                EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
            }
        }
    }
}
