// The guarantees over real sprites: every PNG of pingus-data (about 950
// sprites with alpha), nearest and linear filtering, exact containment.
#include <gtest/gtest.h>

#include "boundary_checks.h"
#include "depthcull/io.h"
#include "testing/corpus.h"

using namespace depthcull;

namespace {

// Sprites over this many texels are skipped to keep the test fast on CI;
// the benchmark covers them.
constexpr std::int64_t kMaxTexels = 512 * 512;

// Linear filtering doubles the grid; every other sprite keeps the test short.
void check_corpus(Filter filter, std::size_t stride) {
    std::string missing = test::corpus_missing("pingus-data");
    if (!missing.empty()) GTEST_SKIP() << missing;
    auto files = test::corpus_files("pingus-data", ".png");
    ASSERT_FALSE(files.empty());
    int checked = 0;
    double boundary = 0, texels = 0;
    for (std::size_t k = 0; k < files.size(); k += stride) {
        const std::string& path = files[k];
        Image img;
        try {
            img = io::read_png(path);
        } catch (const depthcull::Error&) {
            continue; // the io stage's tests cover unreadable files
        }
        if (std::int64_t(img.width) * img.height > kMaxTexels) continue;
        test::FilteredBoundary o;
        o.filter = filter;
        auto polys = test::boundary_polygons(img.view(), img.view().bounds(), o);
        std::string failure = test::boundary_guarantee_failure(img.view(), img.view().bounds(), polys, o);
        ASSERT_EQ(failure, "") << path;
        boundary += total_area(polys);
        for (std::size_t i = 3; i < img.rgba.size(); i += 4) texels += img.rgba[i] != 0;
        ++checked;
    }
    EXPECT_GT(checked, 800 / int(stride));
    // Golden metric with a tolerance: on these sprites our polygons measured
    // 1.269 (nearest) and 1.274 (linear, every other sprite); the bounding
    // boxes of the whole corpus measure 1.64 (bench/bench_boundary.cpp).
    EXPECT_LT(boundary / texels, 1.32);
    std::printf("[ corpus   ] %d sprites, excess area ratio %.4f\n", checked, boundary / texels);
}

} // namespace

TEST(BoundaryCorpus, PingusNearest) { check_corpus(Filter::nearest, 1); }
TEST(BoundaryCorpus, PingusLinear) { check_corpus(Filter::linear, 2); }
