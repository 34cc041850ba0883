// Every Tiled map of the real corpus (scripts/fetch-corpus) imports into a
// valid scene (a refusal would be a one-line "not supported" message).
// Skips when the corpus is absent.
#include <gtest/gtest.h>

#include <cstdio>

#include "depthcull/io.h"
#include "testing/corpus.h"

using namespace depthcull;

namespace {

std::vector<std::string> corpus_maps(const std::string& package) {
    std::vector<std::string> maps = test::corpus_files(package, ".tmx");
    for (const std::string& p : test::corpus_files(package, ".tmx.gz")) maps.push_back(p);
    return maps;
}

void import_all(const std::string& package, int expected_refusals) {
    if (std::string why = test::corpus_missing(package); !why.empty()) GTEST_SKIP() << why;
    std::vector<std::string> maps = corpus_maps(package);
    ASSERT_FALSE(maps.empty());
    int imported = 0, refused = 0;
    std::int64_t elements = 0;
    for (const std::string& path : maps) {
        try {
            Scene s = io::read_scene(path);
            ++imported;
            elements += std::int64_t(s.elements.size());
            EXPECT_FALSE(s.elements.empty()) << path;
            EXPECT_GT(s.viewport.width, 0) << path;
            for (const Element& e : s.elements) {
                ASSERT_GE(e.image, 0) << path;
                ASSERT_LT(std::size_t(e.image), s.images.size()) << path;
                const SceneImage& image = s.images[std::size_t(e.image)];
                ASSERT_TRUE((ImageView{nullptr, image.width, image.height, 0}.contains(e.rect))) << path << ": " << image.path;
            }
        } catch (const depthcull::Error& e) {
            std::string message = e.what();
            ++refused;
            EXPECT_NE(message.find("maps are not supported"), std::string::npos) << message;
            std::printf("  refused: %s\n", message.c_str());
        }
    }
    std::printf("  %s: %zu maps, %d imported (%lld elements), %d refused\n", package.c_str(), maps.size(), imported,
                static_cast<long long>(elements), refused);
    EXPECT_EQ(refused, expected_refusals);
}

} // namespace

TEST(TiledCorpus, TiledExamplesImport) { import_all("tiled", 0); }
TEST(TiledCorpus, BtanksMapsImport) { import_all("btanks-data", 0); }
