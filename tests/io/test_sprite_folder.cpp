// A folder of sprites as a scene (io::read_sprite_folder): every PNG once,
// in path order, in rows that never overlap.
#include <gtest/gtest.h>

#include <filesystem>

#include "test_scene_json_helpers.h"

namespace depthcull::test {
namespace {

TEST(SpriteFolder, EveryPngOnceInRowsWithoutOverlap) {
    SceneDir dir("sprite_folder");
    dir.standard_art();
    std::filesystem::create_directories(dir.path("art/sub"));
    dir.png("art/sub/wide.png", {std::string(1030, '#')});
    dir.write("art/notes.txt", "not an image");
    Scene s = io::read_scene(dir.path("art"));
    ASSERT_EQ(s.images.size(), 3u);
    EXPECT_EQ(s.images[0].id, "blob.png");
    EXPECT_EQ(s.images[1].id, "sub/wide.png");
    EXPECT_EQ(s.images[2].id, "tiles.png");
    ASSERT_EQ(s.elements.size(), 3u);
    // blob (8 wide) at 0,0; wide (1030) does not fit the 1024 px row: next row.
    EXPECT_EQ(s.elements[0].transform[4], 0.0);
    EXPECT_EQ(s.elements[1].transform[4], 0.0);
    EXPECT_EQ(s.elements[1].transform[5], 8.0 + 4.0);
    EXPECT_EQ(s.elements[2].transform[5], 8.0 + 4.0 + 1.0 + 4.0);
    EXPECT_EQ(s.viewport.width, 1030);
    EXPECT_EQ(s.viewport.height, 8 + 4 + 1 + 4 + 8);
    for (std::size_t i = 0; i < s.elements.size(); ++i) EXPECT_EQ(s.elements[i].rect, (Rect{0, 0, s.images[i].width, s.images[i].height}));
    // One PNG is a scene of one element.
    Scene one = io::read_scene(dir.path("art/blob.png"));
    ASSERT_EQ(one.elements.size(), 1u);
    EXPECT_EQ(one.viewport.width, 8);
}

TEST(SpriteFolder, AFolderWithoutPngsIsAnError) {
    SceneDir dir("sprite_folder_empty");
    std::filesystem::create_directories(dir.path("empty"));
    dir.write("empty/readme.txt", "x");
    try {
        io::read_scene(dir.path("empty"));
        FAIL() << "loaded";
    } catch (const depthcull::Error& e) {
        EXPECT_NE(std::string(e.what()).find("no PNG images"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace depthcull::test
