// Tiled's own JSON exports (Tiled 1.8.2, `tiled --export-map json`, made by
// scripts/fetch-corpus when the tiled command is there) of every Tiled
// example map import exactly like the TMX they came from. Skips without
// them.
#include <gtest/gtest.h>

#include <filesystem>

#include "depthcull/io.h"
#include "testing/corpus.h"

using namespace depthcull;

TEST(TiledJsonCorpus, ExportsImportLikeTheirTmx) {
    if (std::string why = test::corpus_missing("tiled-json"); !why.empty()) GTEST_SKIP() << why;
    std::vector<std::string> exports = test::corpus_files("tiled-json", ".export.tmj");
    ASSERT_FALSE(exports.empty());
    for (const std::string& tmj : exports) {
        std::string tmx = tmj.substr(0, tmj.size() - std::string(".export.tmj").size()) + ".tmx";
        Scene a = io::read_scene(tmx), b = io::read_scene(tmj);
        EXPECT_EQ(io::scene_to_json_text(a, ""), io::scene_to_json_text(b, "")) << tmj;
        EXPECT_FALSE(b.elements.empty()) << tmj;
    }
}
