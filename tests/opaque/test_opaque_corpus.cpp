// Golden metrics on the real corpus: both methods keep the guarantee on every
// image checked, the fast method's coverage is never below the paper's for
// the same limits (issue 3), and the replay that guards it is the paper's
// own sequence.
#include <gtest/gtest.h>

#include "depthcull/analyze.h"
#include "depthcull/io.h"
#include "opaque/opaque_internal.h"
#include "testing/corpus.h"

namespace depthcull {
namespace {

// The paper's search is O(w*h^3) and worse with branching, so CI checks a
// deterministic subset: every 3rd pingus sprite (sorted path order) of at
// most 128x128 texels. That is about 240 images and takes about 1 s (paper)
// on one core; set DEPTHCULL_OPAQUE_CORPUS_ALL=1 to check all of them.
bool in_subset(std::size_t index, const Image& image) {
    if (std::getenv("DEPTHCULL_OPAQUE_CORPUS_ALL")) return true;
    return index % 3 == 0 && std::int64_t(image.width) * image.height <= 128 * 128;
}

TEST(OpaqueCorpus, FastCoversAtLeastThePaperOnPingus) {
    if (std::string missing = test::corpus_missing("pingus-data"); !missing.empty()) GTEST_SKIP() << missing;
    auto files = test::corpus_files("pingus-data", ".png");
    ASSERT_FALSE(files.empty());
    int checked = 0;
    std::int64_t paper_total = 0, fast_total = 0;
    for (std::size_t i = 0; i < files.size(); ++i) {
        Image image;
        try {
            image = io::load_png(files[i]);
        } catch (const std::exception&) {
            continue; // unreadable files are io's business
        }
        if (!in_subset(i, image)) continue;
        Rect all = image.view().bounds();
        OpaqueOptions o;
        o.method = OpaqueMethod::paper;
        OpaqueSearchStats paper_stats;
        auto paper = generate_opaque_polygons(image.view(), all, o, Filter::nearest, &paper_stats);
        o.method = OpaqueMethod::fast;
        auto fast = generate_opaque_polygons(image.view(), all, o);
        std::int64_t p = count_covered_opaque_texels(image.view(), all, paper);
        std::int64_t f = count_covered_opaque_texels(image.view(), all, fast);
        // The paper is O(w h^3) and worse (2.2.2): on a few large sprites
        // (mountain, blackboard, ...) it stops at its work budget with the
        // best found so far, which is then what fast is compared with.
        if (paper_stats.budget_exhausted) std::cout << "paper out of budget: " << files[i] << "\n";
        opaque_detail::SearchCounters replay_counters;
        auto replay = opaque_detail::replay_paper_polygons(opaque_mask(image.view(), all), o, replay_counters);
        if (!paper_stats.budget_exhausted && !replay_counters.budget_exhausted) {
            std::vector<Polygon> replayed;
            for (const auto& h : replay) replayed.push_back(opaque_detail::to_polygon(h, all));
            EXPECT_EQ(replayed, paper) << "the replay is not the paper's sequence: " << files[i];
        }
        EXPECT_GE(f, p) << files[i];
        // And in texel centres, the pixels the opaque pass draws at 1:1
        // (issue 25: by squares alone fast drew under 0.9x of the paper's
        // pixels on a few sprites).
        const std::int64_t pc = count_centre_covered_opaque_texels(image.view(), all, paper);
        const std::int64_t fc = count_centre_covered_opaque_texels(image.view(), all, fast);
        EXPECT_GE(fc, pc) << files[i] << ": texel centres";
        if (fc < pc) std::cout << "fast covers " << double(fc) / double(pc) << " of the paper's texel centres: " << files[i] << "\n";
        EXPECT_EQ(count_opaque_violations(image.view(), all, paper, Filter::nearest), 0) << files[i];
        EXPECT_EQ(count_opaque_violations(image.view(), all, fast, Filter::nearest), 0) << files[i];
        paper_total += p;
        fast_total += f;
        ++checked;
    }
    EXPECT_GT(checked, 100);
    EXPECT_GE(fast_total, paper_total);
    std::cout << "checked " << checked << " images: covered texels paper " << paper_total << ", fast " << fast_total
              << "\n";
}

TEST(OpaqueCorpus, LinearFilterGuaranteeOnPingus) {
    if (std::string missing = test::corpus_missing("pingus-data"); !missing.empty()) GTEST_SKIP() << missing;
    auto files = test::corpus_files("pingus-data", ".png");
    int checked = 0;
    for (std::size_t i = 0; i < files.size(); i += 7) {
        Image image;
        try {
            image = io::load_png(files[i]);
        } catch (const std::exception&) {
            continue;
        }
        if (std::int64_t(image.width) * image.height > 256 * 256) continue;
        auto fast = generate_opaque_polygons(image.view(), image.view().bounds(), {}, Filter::linear);
        EXPECT_EQ(count_opaque_violations(image.view(), image.view().bounds(), fast, Filter::linear), 0) << files[i];
        ++checked;
    }
    EXPECT_GT(checked, 50);
}

} // namespace
} // namespace depthcull
