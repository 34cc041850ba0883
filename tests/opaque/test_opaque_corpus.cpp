// Golden metrics on the real corpus: both methods keep the guarantee on every
// image checked, the fast method's coverage is never below the paper's for
// the same limits (issue 3), and the replay that guards it is the paper's
// own sequence.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>

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
            image = io::read_png(files[i]);
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

// cover (issue 25): the guarantee on every image of the subset, and its
// coverage and triangles against fast, the default (printed for the notes;
// DEPTHCULL_OPAQUE_CORPUS_ALL=1 for all images). At the paper's piece cost
// (min_area 64) cover must draw more texel centres than fast in total.
TEST(OpaqueCorpus, CoverOnPingus) {
    if (std::string missing = test::corpus_missing("pingus-data"); !missing.empty()) GTEST_SKIP() << missing;
    auto files = test::corpus_files("pingus-data", ".png");
    ASSERT_FALSE(files.empty());
    struct Totals {
        std::int64_t centres = 0, squares = 0, triangles = 0, polygons = 0;
    };
    auto add = [](Totals& t, const Image& image, const std::vector<Polygon>& polygons) {
        const Rect all = image.view().bounds();
        t.centres += count_centre_covered_opaque_texels(image.view(), all, polygons);
        t.squares += count_covered_opaque_texels(image.view(), all, polygons);
        t.polygons += std::int64_t(polygons.size());
        for (const auto& p : polygons) t.triangles += std::int64_t(p.size()) - 2;
    };
    const int kCosts[] = {64, 16};
    const int kCaps[] = {4, 16, 64};
    Totals fast_totals, cover_totals[2][3];
    std::int64_t opaque = 0;
    int checked = 0, cover_below_fast = 0;
    for (std::size_t i = 0; i < files.size(); ++i) {
        Image image;
        try {
            image = io::read_png(files[i]);
        } catch (const std::exception&) {
            continue;
        }
        if (!in_subset(i, image)) continue;
        const Rect all = image.view().bounds();
        const Mask mask = opaque_mask(image.view(), all);
        opaque += std::count(mask.bits.begin(), mask.bits.end(), 1);
        OpaqueOptions o;
        const auto fast = generate_opaque_polygons(image.view(), all, o);
        add(fast_totals, image, fast);
        o.method = OpaqueMethod::cover;
        for (int c = 0; c < 2; ++c)
            for (int k = 0; k < 3; ++k) {
                o.min_area = kCosts[c];
                o.max_polygons = kCaps[k];
                const auto cover = generate_opaque_polygons(image.view(), all, o);
                ASSERT_EQ(count_opaque_violations(image.view(), all, cover, Filter::nearest), 0) << files[i];
                add(cover_totals[c][k], image, cover);
                if (c == 0 && k == 1 && count_centre_covered_opaque_texels(image.view(), all, cover) <
                                            count_centre_covered_opaque_texels(image.view(), all, fast))
                    ++cover_below_fast;
            }
        ++checked;
    }
    EXPECT_GT(checked, 100);
    auto line = [&](const std::string& name, const Totals& t) {
        std::cout << name << ": centres " << t.centres << " (" << double(t.centres) / double(opaque) << " of "
                  << opaque << " opaque texels), squares " << t.squares << ", polygons " << t.polygons
                  << ", triangles " << t.triangles << "\n";
    };
    std::cout << "checked " << checked << " images\n";
    line("fast (default)", fast_totals);
    for (int c = 0; c < 2; ++c)
        for (int k = 0; k < 3; ++k)
            line("cover min_area " + std::to_string(kCosts[c]) + " max_polygons " + std::to_string(kCaps[k]),
                 cover_totals[c][k]);
    std::cout << "images where cover (64, 16) draws fewer centres than fast: " << cover_below_fast << "\n";
    EXPECT_GT(cover_totals[0][1].centres, fast_totals.centres);
}

TEST(OpaqueCorpus, LinearFilterGuaranteeOnPingus) {
    if (std::string missing = test::corpus_missing("pingus-data"); !missing.empty()) GTEST_SKIP() << missing;
    auto files = test::corpus_files("pingus-data", ".png");
    int checked = 0;
    for (std::size_t i = 0; i < files.size(); i += 7) {
        Image image;
        try {
            image = io::read_png(files[i]);
        } catch (const std::exception&) {
            continue;
        }
        if (std::int64_t(image.width) * image.height > 256 * 256) continue;
        auto fast = generate_opaque_polygons(image.view(), image.view().bounds(), {}, Filter::linear);
        EXPECT_EQ(count_opaque_violations(image.view(), image.view().bounds(), fast, Filter::linear), 0) << files[i];
        OpaqueOptions cover;
        cover.method = OpaqueMethod::cover;
        cover.max_polygons = 64;
        cover.min_area = 16;
        auto pieces = generate_opaque_polygons(image.view(), image.view().bounds(), cover, Filter::linear);
        EXPECT_EQ(count_opaque_violations(image.view(), image.view().bounds(), pieces, Filter::linear), 0) << files[i];
        ++checked;
    }
    EXPECT_GT(checked, 50);
}

} // namespace
} // namespace depthcull
