// TexturePacker atlases: reading both JSON forms, placing trimmed and
// rotated frames so they draw like the untrimmed sprite, and the polygon
// export's round trip (its triangles cover every non-transparent texel).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>

#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "testing/corpus.h"

using namespace depthcull;
namespace fs = std::filesystem;

namespace {

std::string example(const std::string& name) { return test::source_path("examples/atlas/" + name); }

std::string write_temp(const std::string& name, const std::string& text) {
    fs::path dir = fs::temp_directory_path() / ("dc_tp_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir);
    std::string path = (dir / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::string load_error(const std::string& path) {
    try {
        io::read_atlas(path);
    } catch (const depthcull::Error& e) {
        return e.what();
    }
    return "(no error)";
}

// Area of the intersection of a convex polygon (any orientation) with the
// unit square at (x, y): Sutherland-Hodgman against the square's 4 edges.
double clipped_area(std::vector<Vec2> poly, double x, double y) {
    auto clip = [&](auto inside, auto cut) {
        std::vector<Vec2> out;
        for (std::size_t i = 0; i < poly.size(); ++i) {
            Vec2 a = poly[i], b = poly[(i + 1) % poly.size()];
            bool ia = inside(a), ib = inside(b);
            if (ia) out.push_back(a);
            if (ia != ib) out.push_back(cut(a, b));
        }
        poly = out;
    };
    auto at_x = [](Vec2 a, Vec2 b, double X) { return Vec2{X, a.y + (b.y - a.y) * (X - a.x) / (b.x - a.x)}; };
    auto at_y = [](Vec2 a, Vec2 b, double Y) { return Vec2{a.x + (b.x - a.x) * (Y - a.y) / (b.y - a.y), Y}; };
    clip([&](Vec2 p) { return p.x >= x; }, [&](Vec2 a, Vec2 b) { return at_x(a, b, x); });
    clip([&](Vec2 p) { return p.x <= x + 1; }, [&](Vec2 a, Vec2 b) { return at_x(a, b, x + 1); });
    clip([&](Vec2 p) { return p.y >= y; }, [&](Vec2 a, Vec2 b) { return at_y(a, b, y); });
    clip([&](Vec2 p) { return p.y <= y + 1; }, [&](Vec2 a, Vec2 b) { return at_y(a, b, y + 1); });
    return poly.size() < 3 ? 0.0 : area(poly);
}

} // namespace

TEST(TexturePacker, HashFormInFileOrder) {
    io::Atlas atlas = io::read_atlas(example("sheet.json"));
    EXPECT_EQ(atlas.path, example("sheet.json"));
    EXPECT_EQ(fs::path(atlas.image_path).lexically_normal(), fs::path(example("sheet.png")).lexically_normal());
    EXPECT_EQ(atlas.width, 32);
    EXPECT_EQ(atlas.height, 32);
    ASSERT_EQ(atlas.frames.size(), 4u);
    EXPECT_EQ(atlas.frames[0].name, "circle.png");
    EXPECT_EQ(atlas.frames[1].name, "ring.png");
    EXPECT_EQ(atlas.frames[2].name, "ell.png");
    EXPECT_EQ(atlas.frames[3].name, "two-dots.png");
    const io::AtlasFrame& circle = atlas.frames[0];
    EXPECT_EQ(circle.frame, (Rect{0, 0, 10, 10}));
    EXPECT_TRUE(circle.trimmed);
    EXPECT_EQ(circle.sprite_source, (Rect{1, 1, 10, 10}));
    EXPECT_EQ(circle.source_w, 12);
    // Rotated: the JSON's w x h is the sprite (6x10); the page holds 10x6.
    const io::AtlasFrame* ell = atlas.find("ell.png");
    ASSERT_NE(ell, nullptr);
    EXPECT_TRUE(ell->rotated);
    EXPECT_EQ(ell->frame, (Rect{0, 12, 10, 6}));
    EXPECT_EQ(ell->sprite_source, (Rect{2, 0, 6, 10}));
    EXPECT_EQ(atlas.find("nope.png"), nullptr);
}

TEST(TexturePacker, ArrayFormMatchesHashForm) {
    io::Atlas hash = io::read_atlas(example("sheet.json"));
    io::Atlas array = io::read_atlas(example("sheet-array.json"));
    ASSERT_EQ(hash.frames.size(), array.frames.size());
    for (std::size_t i = 0; i < hash.frames.size(); ++i) {
        EXPECT_EQ(hash.frames[i].name, array.frames[i].name);
        EXPECT_EQ(hash.frames[i].frame, array.frames[i].frame);
        EXPECT_EQ(hash.frames[i].rotated, array.frames[i].rotated);
        EXPECT_EQ(hash.frames[i].sprite_source, array.frames[i].sprite_source);
    }
}

TEST(TexturePacker, PlaceTrimmedFrame) {
    io::AtlasFrame f;
    f.frame = {5, 0, 3, 2};
    f.trimmed = true;
    f.sprite_source = {2, 3, 3, 2};
    f.source_w = f.source_h = 8;
    // Sprite placed at (100, 50), scaled 2x.
    io::FramePlacement p = io::place_frame(f, {2, 0, 0, 2, 100, 50});
    EXPECT_EQ(p.rect, f.frame);
    std::array<double, 6> want{2, 0, 0, 2, 104, 56};
    EXPECT_EQ(p.transform, want);
}

// Drawing a rotated frame's element puts every stored texel where the
// sprite's texel of the same colour belongs.
TEST(TexturePacker, PlaceRotatedFrameDrawsTheSprite) {
    io::Atlas atlas = io::read_atlas(example("sheet.json"));
    Image page = io::read_png(atlas.image_path);
    const io::AtlasFrame& ell = *atlas.find("ell.png");
    // The sprite as drawn by hand (before packing): 6x10, the L's bar in
    // columns 0-1 and its foot in rows 8-9, at (2, 0) of the 8x10 source.
    auto sprite_opaque = [](int u, int v) { return u < 2 || v >= 8; };
    io::FramePlacement p = io::place_frame(ell, {1, 0, 0, 1, 0, 0});
    EXPECT_EQ(p.rect, ell.frame);
    int checked = 0;
    for (int t = 0; t < p.rect.h; ++t)
        for (int s = 0; s < p.rect.w; ++s) {
            Vec2 c = apply(p.transform, {s + 0.5, t + 0.5});
            int x = int(std::floor(c.x)), y = int(std::floor(c.y));
            ASSERT_GE(x, 2);
            ASSERT_LT(x, 8);
            ASSERT_GE(y, 0);
            ASSERT_LT(y, 10);
            bool stored = page.view().alpha(p.rect.x + s, p.rect.y + t) != 0;
            EXPECT_EQ(stored, sprite_opaque(x - 2, y)) << "stored texel " << s << "," << t << " -> sprite " << x << "," << y;
            ++checked;
        }
    EXPECT_EQ(checked, 60);
    // Determinant -1 * -1... a pure rotation: no mirror.
    EXPECT_EQ(p.transform[0] * p.transform[3] - p.transform[1] * p.transform[2], 1);
}

TEST(TexturePacker, Errors) {
    struct Case {
        const char* name;
        std::string text;
        std::string expect;
    } cases[] = {
        {"junk", "{\"frames\": [", "not valid JSON at line 1, column "},
        {"no_frames", "{\"meta\": {\"image\": \"a.png\"}}", "no \"frames\""},
        {"no_image", "{\"frames\": {}}", "meta.image"},
        {"multipack", "{\"textures\": []}", "\"textures\" must be a non-empty array of pages"},
        {"bad_rect", "{\"frames\": {\"a\": {\"frame\": {\"x\": 0, \"y\": 0, \"w\": -3, \"h\": 2}}}, \"meta\": {\"image\": \"a.png\"}}",
         "frame 'a': frame: \"w\" = -3 is outside"},
        {"dup", "{\"frames\": [{\"filename\": \"a\", \"frame\": {\"x\": 0, \"y\": 0, \"w\": 1, \"h\": 1}}, {\"filename\": \"a\", \"frame\": {\"x\": 0, \"y\": 0, \"w\": 1, \"h\": 1}}], \"meta\": {\"image\": \"a.png\"}}",
         "frame 'a': duplicate frame name"},
        {"huge", "{\"frames\": {\"a\": {\"frame\": {\"x\": 1e300, \"y\": 0, \"w\": 1, \"h\": 1}}}, \"meta\": {\"image\": \"a.png\"}}",
         "frame 'a': frame: \"x\" = 1e+300 is outside"},
        {"fraction", "{\"frames\": {\"a\": {\"frame\": {\"x\": 0.5, \"y\": 0, \"w\": 1, \"h\": 1}}}, \"meta\": {\"image\": \"a.png\"}}",
         "frame 'a': frame: \"x\" is not an integer"},
    };
    for (const Case& c : cases) {
        std::string path = write_temp(std::string(c.name) + ".json", c.text);
        std::string error = load_error(path);
        EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << c.name << ": " << error;
        EXPECT_NE(error.find(c.expect), std::string::npos) << c.name << ": " << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << c.name << ": " << error;
    }
}

// Round trip: the exported triangles (in verticesUV) cover every
// non-transparent texel of each frame exactly once, vertices are the same
// points in sprite coordinates, and every other field is kept.
TEST(TexturePackerPolygons, RoundTripCoversEveryTexel) {
    for (const char* name : {"sheet.json", "sheet-array.json"}) {
        io::AtlasPolygonStats stats;
        std::string text = pipeline::atlas_with_polygons(example(name), pipeline::AtlasPolygonOptions{}, &stats);
        EXPECT_EQ(text, pipeline::atlas_with_polygons(example(name), pipeline::AtlasPolygonOptions{})); // deterministic
        EXPECT_EQ(stats.frames, 4);
        EXPECT_LT(stats.polygon_area, stats.frame_area);
        std::string path = write_temp(std::string("poly-") + name, text);
        // Still an atlas we (and TexturePacker readers) load, same frames.
        io::Atlas atlas = io::read_atlas(example(name));
        io::Atlas again = io::read_atlas(path);
        ASSERT_EQ(again.frames.size(), atlas.frames.size());
        Image page = io::read_png(atlas.image_path);
        nlohmann::json doc = nlohmann::json::parse(text);
        for (const io::AtlasFrame& frame : atlas.frames) {
            SCOPED_TRACE(frame.name);
            const nlohmann::json& f = doc["frames"].is_array()
                ? *std::find_if(doc["frames"].begin(), doc["frames"].end(), [&](const nlohmann::json& j) { return j["filename"] == frame.name; })
                : doc["frames"][frame.name];
            EXPECT_TRUE(f.contains("pivot"));
            const auto& uv = f["verticesUV"];
            const auto& xy = f["vertices"];
            ASSERT_EQ(uv.size(), xy.size());
            std::vector<std::vector<Vec2>> triangles;
            for (const auto& t : f["triangles"]) {
                std::vector<Vec2> tri;
                for (int k = 0; k < 3; ++k) {
                    std::size_t i = t[std::size_t(k)].get<std::size_t>();
                    ASSERT_LT(i, uv.size());
                    tri.push_back({uv[i][0].get<double>(), uv[i][1].get<double>()});
                }
                triangles.push_back(tri);
            }
            // Sprite coordinates: drawing the frame with place_frame puts UV point p at vertex xy.
            io::FramePlacement placed = io::place_frame(frame, {1, 0, 0, 1, 0, 0});
            for (std::size_t i = 0; i < uv.size(); ++i) {
                Vec2 p = apply(placed.transform, {uv[i][0].get<double>() - frame.frame.x, uv[i][1].get<double>() - frame.frame.y});
                EXPECT_DOUBLE_EQ(p.x, xy[i][0].get<double>());
                EXPECT_DOUBLE_EQ(p.y, xy[i][1].get<double>());
            }
            int nontransparent = 0;
            for (int y = frame.frame.y; y < frame.frame.y + frame.frame.h; ++y)
                for (int x = frame.frame.x; x < frame.frame.x + frame.frame.w; ++x) {
                    if (page.view().alpha(x, y) == 0) continue;
                    ++nontransparent;
                    double covered = 0;
                    for (const auto& tri : triangles) covered += clipped_area(tri, x, y);
                    EXPECT_NEAR(covered, 1.0, 1e-9) << "texel " << x << "," << y;
                }
            EXPECT_GT(nontransparent, 0);
        }
    }
}

// Corrupted atlases never crash: each mutation loads or throws depthcull::Error.
TEST(TexturePacker, MutatedAtlasesFailCleanly) {
    std::mt19937 rng(777);
    for (const char* name : {"sheet.json", "sheet-array.json"}) {
        std::string text = io::read_file(example(name));
        std::string path = write_temp(std::string("m_") + name, "");
        for (int round = 0; round < 60; ++round) {
            std::string mutated = text;
            for (int k = 0, edits = 1 + int(rng() % 3); k < edits; ++k) {
                std::size_t at = rng() % mutated.size();
                switch (rng() % 3) {
                case 0: mutated[at] = "0123456789-.e{}[]\",:tn"[rng() % 23]; break;
                case 1: mutated.erase(at, 1 + rng() % 6); break;
                default: mutated.insert(at, 1, "0123456789-.e{}[]\",:"[rng() % 20]); break;
                }
                if (mutated.empty()) mutated = "{";
            }
            std::ofstream(path, std::ios::binary | std::ios::trunc) << mutated;
            try {
                io::Atlas atlas = io::read_atlas(path);
                for (const io::AtlasFrame& f : atlas.frames) {
                    EXPECT_FALSE(f.frame.empty());
                    EXPECT_GE(f.frame.x, 0);
                }
            } catch (const depthcull::Error& e) {
                EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
            }
        }
    }
}
