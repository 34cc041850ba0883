// The scene JSON reader: fields, defaults, and one-line errors that name
// the file and the element index.
#include <gtest/gtest.h>

#include "test_scene_json_helpers.h"

namespace depthcull::test {
namespace {

std::string scene_text(const std::string& elements, const std::string& extra = "") {
    return R"({"viewport": {"width": 64, "height": 48}, )" + extra +
           R"("images": [{"id": "blob", "path": "art/blob.png"}, {"id": "tiles", "path": "art/tiles.png"}],
              "elements": [)" + elements + "]}";
}

std::string load_error(const SceneDir& dir, const std::string& text) {
    std::string path = dir.write("scene.json", text);
    try {
        io::read_scene(path);
    } catch (const depthcull::Error& e) {
        return e.what();
    }
    return "";
}

TEST(SceneJson, LoadsFieldsAndDefaults) {
    SceneDir dir("scene_json");
    dir.standard_art();
    std::string path = dir.write("scene.json", scene_text(R"(
        {"image": "blob"},
        {"image": "tiles", "rect": [8, 0, 8, 8], "transform": [0, 1, -1, 0, 30, 5], "color": [1, 0.5, 0.25, 0.75],
         "blend": "add", "unknown_field": 3})",
                                                              R"("filter": "linear", )"));
    Scene s = io::read_scene(path);
    EXPECT_EQ(s.viewport.width, 64);
    EXPECT_EQ(s.viewport.height, 48);
    EXPECT_EQ(s.filter, Filter::linear);
    ASSERT_EQ(s.images.size(), 2u);
    EXPECT_EQ(s.images[0].width, 8);
    EXPECT_EQ(s.images[1].width, 16);
    EXPECT_TRUE(std::filesystem::exists(s.images[0].path));
    ASSERT_EQ(s.elements.size(), 2u);
    EXPECT_EQ(s.elements[0].rect, (Rect{0, 0, 8, 8}));
    EXPECT_EQ(s.elements[0].blend, Blend::alpha);
    EXPECT_EQ(s.elements[0].color[3], 1.0f);
    EXPECT_EQ(s.elements[1].image, 1);
    EXPECT_EQ(s.elements[1].rect, (Rect{8, 0, 8, 8}));
    EXPECT_EQ(s.elements[1].transform[2], -1.0);
    EXPECT_EQ(s.elements[1].color[2], 0.25f);
    EXPECT_EQ(s.elements[1].blend, Blend::add);
}

// With LoadOptions::image_files the loader reads each image file whole,
// once, for its size, and the decode takes those bytes instead of opening
// the file again (pipeline::prepare_scene: one open per file): the files
// may be gone by then. Without, the loader reads headers only; the sizes
// are the same.
TEST(SceneJson, ImageFilesAreReadOnceAndDecodedFromMemory) {
    SceneDir dir("scene_json_files");
    dir.standard_art();
    const std::string path = dir.write("scene.json", scene_text(R"({"image": "blob"}, {"image": "tiles"}, {"image": "blob"})"));
    io::ImageFiles files;
    io::LoadOptions options;
    options.image_files = &files;
    const Scene s = io::read_scene(path, options), plain = io::read_scene(path);
    ASSERT_EQ(s.images.size(), 2u);
    std::vector<Image> from_disk;
    for (std::size_t i = 0; i < s.images.size(); ++i) {
        EXPECT_NE(files.find(s.images[i].path), nullptr) << i;
        EXPECT_EQ(s.images[i].width, plain.images[i].width) << i;
        EXPECT_EQ(s.images[i].height, plain.images[i].height) << i;
        from_disk.push_back(io::read_scene_image(s.images[i]));
    }
    std::filesystem::remove_all(dir.path("art"));
    for (std::size_t i = 0; i < s.images.size(); ++i) {
        const Image decoded = io::read_scene_image(s.images[i], &files);
        EXPECT_EQ(decoded.width, from_disk[i].width) << i;
        EXPECT_EQ(decoded.rgba, from_disk[i].rgba) << i;
    }
    EXPECT_THROW(io::read_scene_image(s.images[0]), depthcull::Error);
}

// Past its budget ImageFiles keeps nothing more: the loader reads such a
// file's size as without it, and the decode reads the file from disk.
TEST(SceneJson, ImageFilesPastTheirBudgetAreReadAgain) {
    SceneDir dir("scene_json_budget");
    dir.standard_art();
    const std::string path = dir.write("scene.json", scene_text(R"({"image": "blob"}, {"image": "tiles"})"));
    const auto blob = std::filesystem::file_size(dir.path("art/blob.png"));
    io::ImageFiles files(blob); // room for blob.png alone
    io::LoadOptions options;
    options.image_files = &files;
    const Scene s = io::read_scene(path, options);
    EXPECT_NE(files.find(s.images[0].path), nullptr);
    EXPECT_EQ(files.find(s.images[1].path), nullptr);
    EXPECT_EQ(s.images[1].width, io::read_scene(path).images[1].width);
    EXPECT_EQ(io::read_scene_image(s.images[1], &files).rgba, io::read_scene_image(s.images[1]).rgba);
}

TEST(SceneJson, ColourKeysAreReadAndWrittenBack) {
    SceneDir dir("scene_json_trans");
    dir.standard_art();
    std::string path = dir.write("scene.json", R"({"images": [{"id": "blob", "path": "art/blob.png", "trans": "#FF00ff"}],
                                                   "elements": [{"image": "blob"}]})");
    Scene s = io::read_scene(path);
    ASSERT_TRUE(s.images[0].has_trans);
    EXPECT_EQ(s.images[0].trans, 0xff00ffu);
    std::string text = io::scene_to_json_text(s, path);
    EXPECT_NE(text.find("\"trans\":\"ff00ff\""), std::string::npos) << text;
    Scene again = io::read_scene(dir.write("again.json", text));
    EXPECT_TRUE(again.images[0].has_trans);
    EXPECT_EQ(again.images[0].trans, 0xff00ffu);
    std::string e = load_error(dir, R"({"images": [{"id": "blob", "path": "art/blob.png", "trans": "red"}], "elements": []})");
    EXPECT_NE(e.find("scene.json"), std::string::npos) << e;
    EXPECT_NE(e.find("colour key"), std::string::npos) << e;
}

TEST(SceneJson, ViewportOverrideAndDefault) {
    SceneDir dir("scene_json_vp");
    dir.standard_art();
    std::string path = dir.write("scene.json", R"({"images": [{"id": "blob", "path": "art/blob.png"}],
        "elements": [{"image": "blob", "transform": [2, 0, 0, 2, 10, 20]}]})");
    Scene s = io::read_scene(path);
    EXPECT_EQ(s.viewport.x, 10);
    EXPECT_EQ(s.viewport.width, 16); // the elements' bounds
    io::LoadOptions o;
    o.has_viewport = true;
    o.viewport = {1, 2, 30, 40};
    EXPECT_EQ(io::read_scene(path, o).viewport.height, 40);
}

TEST(SceneJson, ErrorsNameTheFileAndElement) {
    SceneDir dir("scene_json_err");
    dir.standard_art();
    auto has = [](const std::string& message, const std::string& part) {
        return message.find(part) != std::string::npos && message.find('\n') == std::string::npos;
    };
    EXPECT_PRED2(has, load_error(dir, scene_text(R"({"image": "blob"}, {"image": "rok"})")), "element 1: unknown image id \"rok\"");
    EXPECT_PRED2(has, load_error(dir, scene_text(R"({"image": "blob", "rect": [0, 0, -1, 4]})")), "element 0: \"rect\" must have a positive size");
    EXPECT_PRED2(has, load_error(dir, scene_text(R"({"image": "tiles", "rect": [12, 0, 8, 8]})")), "element 0: rect 12,0,8,8 is outside the 16x8 image");
    EXPECT_PRED2(has, load_error(dir, scene_text(R"({"image": "blob", "transform": [1, 0, 0, 1, "x", 0]})")), "element 0: transform must be a number");
    EXPECT_PRED2(has, load_error(dir, scene_text(R"({"image": "blob", "transform": [1, 0, 0]})")), "element 0: \"transform\" must be an array of 6 numbers");
    EXPECT_PRED2(has, load_error(dir, scene_text(R"({"image": "blob", "color": [1, 1, 1, 2]})")), "element 0: \"color\" components must be in 0..1");
    EXPECT_PRED2(has, load_error(dir, scene_text(R"({"image": "blob", "blend": "screen"})")), "element 0: unknown blend \"screen\"");
    EXPECT_PRED2(has, load_error(dir, R"({"images": [{"id": "x", "path": "art/missing.png"}], "elements": []})"), "image 0: cannot open image");
    EXPECT_PRED2(has, load_error(dir, R"({"images": [{"id": "x", "path": "art/blob.png"}, {"id": "x", "path": "art/blob.png"}], "elements": []})"),
                 "image 1: duplicate image id \"x\"");
    EXPECT_PRED2(has, load_error(dir, "{\"images\": ["), "scene.json: not valid JSON");
    EXPECT_PRED2(has, load_error(dir, scene_text("", R"("viewport": {"width": 0, "height": 5}, )")), "viewport: width and height");
}

TEST(SceneJson, AtlasFramesResolveThroughTexturePacker) {
    const std::string atlas = std::string(DEPTHCULL_SOURCE_DIR) + "/examples/atlas/sheet.json";
    if (!std::filesystem::exists(atlas)) GTEST_SKIP() << "no bundled atlas at " << atlas;
    SceneDir dir("scene_json_atlas");
    std::string images = R"("images": [{"id": "sheet", "atlas": ")" + atlas + R"("}], )";
    std::string path = dir.write("scene.json", "{" + images + R"("elements": [
        {"image": "sheet", "frame": "circle.png", "transform": [1, 0, 0, 1, 5, 5]},
        {"image": "sheet", "frame": "ring.png"}]})");
    Scene s = io::read_scene(path);
    ASSERT_EQ(s.elements.size(), 2u);
    const io::Atlas sheet = io::read_atlas(atlas);
    EXPECT_EQ(s.images[0].path, sheet.image_path);
    for (std::size_t i = 0; i < 2; ++i) {
        const io::AtlasFrame* frame = sheet.find(i == 0 ? "circle.png" : "ring.png");
        ASSERT_NE(frame, nullptr);
        io::FramePlacement placed = io::place_frame(*frame, i == 0 ? std::array<double, 6>{1, 0, 0, 1, 5, 5}
                                                                   : std::array<double, 6>{1, 0, 0, 1, 0, 0});
        EXPECT_EQ(s.elements[i].rect, placed.rect);
        EXPECT_EQ(s.elements[i].transform, placed.transform);
    }
    std::string bad = dir.write("bad.json", "{" + images + R"("elements": [{"image": "sheet"}, {"image": "sheet", "frame": "nope.png"}]})");
    try {
        io::read_scene(bad);
        ADD_FAILURE() << "expected an error";
    } catch (const depthcull::Error& e) {
        EXPECT_NE(std::string(e.what()).find("element 1: atlas \"sheet\" has no frame \"nope.png\""), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace depthcull::test
