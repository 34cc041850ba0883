// Atlases packed by a real packer (free-tex-packer-core 0.3.9, pingus
// sprites, rotation and trimming; scripts/atlas-fixtures): TexturePacker
// JSON hash and array, the Phaser 3 multipack and a cocos2d plist read
// alike; polygons written into a multipack and into a cocos2d-x format 3
// plist; spriteSourceSize sizes that differ from the frame's.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "depthcull/io.h"
#include "test_scene_json_helpers.h"
#include "depthcull/pipeline.h"
#include "testing/corpus.h"
#include <nlohmann/json.hpp>

using namespace depthcull;
namespace fs = std::filesystem;

namespace {

std::string packed(const std::string& name) { return test::source_path("tests/data/atlas/packed/" + name); }

std::string error_of(const std::function<void()>& fn) {
    try {
        fn();
    } catch (const depthcull::Error& e) {
        return e.what();
    }
    return "(no error)";
}

// A scratch directory named after the running test.
struct TempDir : test::SceneDir {
    TempDir() : SceneDir("atlas_formats_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())) {}
    const fs::path& dir = root;
};

void expect_same_frame(const io::AtlasFrame& a, const io::AtlasFrame& b, const std::string& form) {
    EXPECT_EQ(a.frame, b.frame) << form << " " << a.name;
    EXPECT_EQ(a.rotated, b.rotated) << form << " " << a.name;
    EXPECT_EQ(a.sprite_source, b.sprite_source) << form << " " << a.name;
    EXPECT_EQ(a.source_w, b.source_w) << form << " " << a.name;
    EXPECT_EQ(a.source_h, b.source_h) << form << " " << a.name;
}

std::vector<int> ints(const std::string& text) {
    std::istringstream in(text);
    std::vector<int> out;
    for (int v; in >> v;) out.push_back(v);
    return out;
}

// The value of <key>key</key><string>...</string> after `from` in a plist.
std::string plist_string(const std::string& text, const std::string& frame, const std::string& key) {
    std::size_t at = text.find("<key>" + frame + "</key>");
    at = text.find("<key>" + key + "</key>", at);
    std::size_t open = text.find("<string>", at) + 8;
    return text.substr(open, text.find("</string>", open) - open);
}

} // namespace

TEST(AtlasFormats, EveryPackedFormReadsTheSameFrames) {
    io::Atlas hash = io::read_atlas(packed("hash-0.json"));
    EXPECT_EQ(hash.form, io::AtlasForm::json_hash);
    ASSERT_EQ(hash.frames.size(), 6u);
    // Exact, from the packer's output: a rotated trimmed frame and a trimmed one.
    const io::AtlasFrame* turned = hash.find("chalk_pingu2.png");
    ASSERT_TRUE(turned);
    EXPECT_TRUE(turned->rotated);
    EXPECT_EQ(turned->frame, (Rect{30, 18, 20, 13})); // stored 20 wide, 13 high
    EXPECT_EQ(turned->sprite_source, (Rect{1, 0, 13, 20}));
    EXPECT_EQ(turned->source_w, 15);
    const io::AtlasFrame* next = hash.find("next.png");
    ASSERT_TRUE(next);
    EXPECT_EQ(next->frame, (Rect{1, 1, 50, 15}));
    EXPECT_EQ(next->sprite_source, (Rect{8, 6, 50, 15}));
    EXPECT_EQ(next->source_w, 63);
    EXPECT_EQ(next->source_h, 25);

    io::Atlas array = io::read_atlas(packed("array-0.json"));
    io::Atlas multi = io::read_atlas(packed("phaser3-multi.json"));
    io::Atlas plist = io::read_atlas(packed("cocos2d-0.plist"));
    EXPECT_EQ(array.form, io::AtlasForm::json_array);
    EXPECT_EQ(multi.form, io::AtlasForm::json_multipack);
    EXPECT_EQ(plist.form, io::AtlasForm::cocos2d_plist);
    EXPECT_EQ(plist.plist_format, 2);
    EXPECT_EQ(plist.image_path, packed("cocos2d-0.png"));
    ASSERT_EQ(multi.pages.size(), 2u);
    EXPECT_EQ(multi.pages[1].image_path, packed("phaser3-1.png"));
    EXPECT_EQ(multi.frames.size(), 7u);
    const io::AtlasFrame* infinity = multi.find("infinity.png");
    ASSERT_TRUE(infinity);
    EXPECT_EQ(infinity->page, 1);
    for (const io::AtlasFrame& f : hash.frames) {
        for (const io::Atlas* other : {&array, &multi, &plist}) {
            const io::AtlasFrame* g = other->find(f.name);
            ASSERT_TRUE(g) << f.name;
            expect_same_frame(f, *g, other->path);
            EXPECT_EQ(g->page, 0);
        }
    }
}

TEST(AtlasFormats, PolygonsInEveryPageOfAMultipack) {
    pipeline::AtlasPolygonOptions options;
    io::AtlasPolygonStats stats;
    std::string text = pipeline::atlas_with_polygons(packed("phaser3-multi.json"), options, &stats);
    EXPECT_EQ(stats.frames, 7);
    auto doc = nlohmann::json::parse(text);
    ASSERT_EQ(doc["textures"].size(), 2u);
    const auto& inf = doc["textures"][1]["frames"][0];
    EXPECT_EQ(inf["filename"], "infinity.png");
    EXPECT_GE(inf["vertices"].size(), 3u);
    EXPECT_EQ(inf["vertices"].size(), inf["verticesUV"].size());
    // The same polygons as the single-page JSON for frames of page 0.
    auto hash = nlohmann::json::parse(pipeline::atlas_with_polygons(packed("hash-0.json"), options, nullptr));
    for (const auto& f : doc["textures"][0]["frames"]) EXPECT_EQ(f["vertices"], hash["frames"][f["filename"].get<std::string>()]["vertices"]);
}

TEST(AtlasFormats, Cocos2dFormat3PlistWithPolygonsRoundTrips) {
    TempDir t;
    fs::copy_file(packed("hash-0.png"), t.dir / "hash-0.png");
    fs::copy_file(packed("hash-0.json"), t.dir / "hash-0.json");
    pipeline::AtlasPolygonOptions options;
    options.plist = true;
    io::AtlasPolygonStats stats;
    std::string text = pipeline::atlas_with_polygons((t.dir / "hash-0.json").string(), options, &stats);
    EXPECT_EQ(stats.rectangle_frames, 0);
    std::string path = t.write("out.plist", text);
    io::Atlas back = io::read_atlas(path);
    EXPECT_EQ(back.plist_format, 3);
    io::Atlas hash = io::read_atlas(packed("hash-0.json"));
    ASSERT_EQ(back.frames.size(), hash.frames.size());
    for (std::size_t i = 0; i < hash.frames.size(); ++i) {
        EXPECT_EQ(back.frames[i].name, hash.frames[i].name);
        expect_same_frame(hash.frames[i], back.frames[i], "plist");
    }
    // The polygon fields as cocos2d-x reads them (space-separated integers):
    // the triangles, in page texels, cover every non-transparent texel.
    Image page = io::read_image(packed("hash-0.png"));
    for (const io::AtlasFrame& f : hash.frames) {
        std::vector<int> tri = ints(plist_string(text, f.name, "triangles"));
        std::vector<int> uv = ints(plist_string(text, f.name, "verticesUV"));
        std::vector<int> xy = ints(plist_string(text, f.name, "vertices"));
        ASSERT_EQ(uv.size(), xy.size()) << f.name;
        ASSERT_EQ(tri.size() % 3, 0u) << f.name;
        std::vector<Polygon> triangles;
        for (std::size_t k = 0; k < tri.size(); k += 3) {
            Polygon p;
            for (int j = 0; j < 3; ++j) p.push_back({double(uv[2 * std::size_t(tri[k + std::size_t(j)])]), double(uv[2 * std::size_t(tri[k + std::size_t(j)]) + 1])});
            triangles.push_back(p);
        }
        // A texel may straddle two triangles of one polygon: check against
        // the union by counting texels each triangle set misses as a whole.
        ImageAnalysis a = analyze_image(page.view(), f.frame, {});
        std::int64_t missed_by_polygons = count_uncontained_texels(page.view(), f.frame, a.boundary, Filter::nearest);
        EXPECT_EQ(missed_by_polygons, 0) << f.name;
        double tri_area = 0;
        for (const Polygon& p : triangles) tri_area += std::abs(area(p));
        double poly_area = 0;
        for (const Polygon& p : a.boundary) poly_area += std::abs(area(p));
        EXPECT_DOUBLE_EQ(tri_area, poly_area) << f.name; // the triangles tile the polygons exactly
        // vertices = verticesUV mapped to the untrimmed sprite.
        if (!f.rotated) {
            for (std::size_t k = 0; k < xy.size(); k += 2) {
                EXPECT_EQ(xy[k], uv[k] - f.frame.x + f.sprite_source.x) << f.name;
                EXPECT_EQ(xy[k + 1], uv[k + 1] - f.frame.y + f.sprite_source.y) << f.name;
            }
        }
    }
    // format 3's spriteOffset for next.png: centre (8 + 25, 6 + 7.5) vs (31.5, 12.5), y up.
    EXPECT_EQ(plist_string(text, "next.png", "spriteOffset"), "{1.5,-1}");
}

TEST(AtlasFormats, SpriteSourceSizeLargerThanTheFrame) {
    TempDir t;
    fs::copy_file(packed("hash-0.png"), t.dir / "page.png");
    // Flash-style: spriteSourceSize w/h give the untrimmed size; the frame's
    // size is the trimmed sprite's (as Phaser and PixiJS read it).
    std::string path = t.write("flash.json", R"({"frames": {"n": {"frame": {"x": 1, "y": 1, "w": 50, "h": 15}, "rotated": false, "trimmed": true,
        "spriteSourceSize": {"x": 8, "y": 6, "w": 63, "h": 25}, "sourceSize": {"w": 63, "h": 25}}}, "meta": {"image": "page.png"}})");
    io::Atlas a = io::read_atlas(path);
    ASSERT_EQ(a.frames.size(), 1u);
    EXPECT_EQ(a.frames[0].sprite_source, (Rect{8, 6, 50, 15}));
    EXPECT_EQ(a.frames[0].frame, (Rect{1, 1, 50, 15}));
}

TEST(AtlasFormats, RefusalsAreOneLine) {
    TempDir t;
    std::string old = t.write("old.plist", "<plist><dict><key>frames</key><dict/><key>metadata</key><dict><key>format</key><integer>1</integer></dict></dict></plist>");
    EXPECT_EQ(error_of([&] { io::read_atlas(old); }), old + ": cocos2d plist format 1 is not supported (formats 2 and 3 are)");
    pipeline::AtlasPolygonOptions options;
    options.plist = true;
    EXPECT_EQ(error_of([&] { pipeline::atlas_with_polygons(packed("phaser3-multi.json"), options, nullptr); }),
              packed("phaser3-multi.json") + ": a cocos2d-x plist holds one page; this multipack has 2 (write JSON, or one plist per page)");
    std::string dup = t.write("dup.json", R"({"textures": [{"image": "a.png", "frames": [{"filename": "x", "frame": {"x": 0, "y": 0, "w": 1, "h": 1}}]},
        {"image": "b.png", "frames": [{"filename": "x", "frame": {"x": 0, "y": 0, "w": 1, "h": 1}}]}]})");
    EXPECT_EQ(error_of([&] { io::read_atlas(dup); }), dup + ": frame 'x': duplicate frame name");
}

TEST(AtlasFormats, SceneFramesOfAMultipackUseTheirPage) {
    TempDir t;
    std::string scene = t.write("s.json", R"({"images": [{"id": "ui", "atlas": ")" + packed("phaser3-multi.json") + R"("}],
        "elements": [{"image": "ui", "frame": "next.png"}, {"image": "ui", "frame": "infinity.png", "transform": [1, 0, 0, 1, 70, 0]}]})");
    Scene s = io::read_scene(scene);
    ASSERT_EQ(s.images.size(), 2u);
    EXPECT_EQ(s.images[1].id, "ui#1");
    EXPECT_EQ(s.images[1].path, packed("phaser3-1.png"));
    ASSERT_EQ(s.elements.size(), 2u);
    EXPECT_EQ(s.elements[0].image, 0);
    EXPECT_EQ(s.elements[1].image, 1);
}

// The bigger atlases scripts/fetch-corpus packs (pingus sprites, pages of
// 256 px): every form reads the same frames and gets polygons.
TEST(AtlasFormatsCorpus, PackedAtlasesAgree) {
    if (std::string why = test::corpus_missing("packed-atlases"); !why.empty()) GTEST_SKIP() << why;
    const std::string dir = test::corpus_dir() + "/packed-atlases/";
    io::Atlas multi = io::read_atlas(dir + "phaser3-multi.json");
    std::size_t pages = multi.pages.size(), seen = 0;
    for (std::size_t k = 0; k < pages; ++k) {
        const std::string n = std::to_string(k);
        for (const std::string& name : {"hash-" + n + ".json", "array-" + n + ".json", "cocos2d-" + n + ".plist"}) {
            io::Atlas a = io::read_atlas(dir + name);
            for (const io::AtlasFrame& f : a.frames) {
                const io::AtlasFrame* g = multi.find(f.name);
                ASSERT_TRUE(g) << name << " " << f.name;
                EXPECT_EQ(g->page, int(k)) << f.name;
                expect_same_frame(f, *g, name);
            }
            if (name[0] == 'h') seen += a.frames.size();
            pipeline::AtlasPolygonOptions options;
            io::AtlasPolygonStats stats;
            pipeline::atlas_with_polygons(dir + name, options, &stats);
            EXPECT_EQ(std::size_t(stats.frames), a.frames.size()) << name;
            EXPECT_EQ(stats.rectangle_frames, 0) << name;
        }
    }
    EXPECT_EQ(seen, multi.frames.size());
}
