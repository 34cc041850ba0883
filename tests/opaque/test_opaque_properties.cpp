// Property tests: the guarantee of analyze.h for every method and both
// filters over random shapes, the shape of the output (convex, clockwise,
// half grid, inside the rect, count), and the exact arithmetic underneath.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "depthcull/analyze.h"
#include "opaque/opaque_internal.h"
#include "testing/convex_hull.h"
#include "testing/random_shapes.h"

namespace depthcull {
namespace {

// Options and the filter they are searched for (AnalyzeOptions::filter).
struct FilteredOptions : OpaqueOptions {
    Filter filter = Filter::nearest;
};

void check_guarantee(const Image& image, Rect rect, const FilteredOptions& o) {
    auto polygons = generate_opaque_polygons(image.view(), rect, o, o.filter);
    RC_ASSERT(int(polygons.size()) <= std::max(0, o.max_polygons));
    RC_TAG(polygons.empty() ? "no polygon" : "polygons");
    RC_ASSERT(count_opaque_violations(image.view(), rect, polygons, o.filter) == 0);
    for (const auto& p : polygons) {
        RC_ASSERT(p.size() >= 3u);
        RC_ASSERT(is_convex(p));
        RC_ASSERT(signed_area(p) > 0); // clockwise, y down
        // Half grid; 1/16 of a texel for cover.
        const double grid = o.method == OpaqueMethod::cover ? 16 : 2;
        RC_ASSERT(p.size() <= std::size_t(kMaxOpaqueVertices));
        for (const auto& v : p) {
            RC_ASSERT(v.x * grid == std::floor(v.x * grid));
            RC_ASSERT(v.y * grid == std::floor(v.y * grid));
            RC_ASSERT(v.x >= rect.x && v.x <= rect.x + rect.w);
            RC_ASSERT(v.y >= rect.y && v.y <= rect.y + rect.h);
        }
    }
}

constexpr OpaqueMethod kMethods[] = {OpaqueMethod::paper, OpaqueMethod::fast, OpaqueMethod::grow,
                                     OpaqueMethod::cover};

FilteredOptions options(OpaqueMethod method, Filter filter, int min_area, int max_polygons) {
    FilteredOptions o;
    o.method = method;
    o.filter = filter;
    o.min_area = min_area;
    o.max_polygons = max_polygons;
    return o;
}

RC_GTEST_PROP(OpaqueProperties, GuaranteeHoldsForEveryMethodAndFilter, ()) {
    Image image = *test::gen_shape(40);
    const int min_area = *rc::gen::inRange(1, 40);
    const int max_polygons = *rc::gen::inRange(1, 7);
    for (auto method : kMethods)
        for (auto filter : {Filter::nearest, Filter::linear})
            check_guarantee(image, image.view().bounds(), options(method, filter, min_area, max_polygons));
}

// Larger, mostly solid shapes, so most cases do produce polygons.
rc::Gen<Image> gen_solid_shape() {
    return rc::gen::apply(
        [](std::uint64_t seed, int w, int h, int blobs, int holes, bool rim, bool noise) {
            return test::random_shape(seed, {w, h, blobs, holes, rim, noise});
        },
        rc::gen::arbitrary<std::uint64_t>(), rc::gen::inRange(8, 72), rc::gen::inRange(8, 72), rc::gen::inRange(1, 5),
        rc::gen::inRange(0, 4), rc::gen::arbitrary<bool>(),
        rc::gen::weightedOneOf<bool>({{5, rc::gen::just(false)}, {1, rc::gen::just(true)}}));
}

RC_GTEST_PROP(OpaqueProperties, GuaranteeHoldsOnSolidShapes, ()) {
    Image image = *gen_solid_shape();
    const int min_area = *rc::gen::inRange(1, 40);
    for (auto method : kMethods)
        for (auto filter : {Filter::nearest, Filter::linear})
            check_guarantee(image, image.view().bounds(), options(method, filter, min_area, 6));
}

RC_GTEST_PROP(OpaqueProperties, GuaranteeHoldsInSubRects, ()) {
    Image image = *test::gen_shape(40);
    const int x = *rc::gen::inRange(0, image.width), y = *rc::gen::inRange(0, image.height);
    const int w = *rc::gen::inRange(0, image.width - x + 1), h = *rc::gen::inRange(0, image.height - y + 1);
    for (auto method : kMethods)
        check_guarantee(image, {x, y, w, h}, options(method, Filter::nearest, 1, 4));
}

RC_GTEST_PROP(OpaqueProperties, FastCoversAtLeastThePaper, ()) {
    Image image = *gen_solid_shape();
    const int min_area = *rc::gen::inRange(1, 64);
    Rect all = image.view().bounds();
    auto paper = generate_opaque_polygons(image.view(), all, options(OpaqueMethod::paper, Filter::nearest, min_area, 4));
    auto fast = generate_opaque_polygons(image.view(), all, options(OpaqueMethod::fast, Filter::nearest, min_area, 4));
    RC_ASSERT(count_covered_opaque_texels(image.view(), all, fast) >=
              count_covered_opaque_texels(image.view(), all, paper));
}

// The guard of `fast` is only as good as its replay: it must choose exactly
// the paper's polygons, in order.
RC_GTEST_PROP(OpaqueProperties, ReplayIsThePapersSequence, ()) {
    Image image = *gen_solid_shape();
    const int min_area = *rc::gen::inRange(1, 64);
    const int max_polygons = *rc::gen::inRange(1, 7);
    const OpaqueOptions o = options(OpaqueMethod::paper, Filter::nearest, min_area, max_polygons);
    const Mask safe = opaque_mask(image.view(), image.view().bounds());
    opaque_detail::SearchCounters paper_counters, replay_counters;
    auto paper = opaque_detail::paper_opaque_polygons(safe, o, paper_counters);
    auto replay = opaque_detail::replay_paper_polygons(safe, o, replay_counters);
    RC_PRE(!paper_counters.budget_exhausted && !replay_counters.budget_exhausted);
    RC_TAG(paper.empty() ? "no polygon" : "polygons");
    RC_ASSERT(replay == paper);
}

TEST(OpaqueProperties, Deterministic) {
    test::ShapeParams params;
    params.width = params.height = 64;
    params.holes = 3;
    Image image = test::random_shape(7, params);
    for (auto method : kMethods) {
        OpaqueOptions o = options(method, Filter::nearest, 8, 4);
        EXPECT_EQ(generate_opaque_polygons(image.view(), image.view().bounds(), o),
                  generate_opaque_polygons(image.view(), image.view().bounds(), o));
    }
}

TEST(OpaqueProperties, EmptyAndTransparentInputs) {
    Image empty;
    EXPECT_TRUE(generate_opaque_polygons(empty.view(), {0, 0, 0, 0}, {}).empty());
    test::ShapeParams params;
    params.blobs = 0;
    Image clear = test::random_shape(1, params);
    for (auto method : kMethods) {
        OpaqueOptions o = options(method, Filter::nearest, 1, 4);
        EXPECT_TRUE(generate_opaque_polygons(clear.view(), clear.view().bounds(), o).empty());
        // A rect outside the image is rejected, not read.
        EXPECT_TRUE(generate_opaque_polygons(clear.view(), {30, 30, 10, 10}, o).empty());
    }
}

// ---- cover (issue 25): the opaque region in convex pieces.

// The pieces never overlap (each lies in its own stack's rows and runs), so
// the opaque pass draws no pixel of an element twice: every texel centre
// they cover is covered once.
RC_GTEST_PROP(OpaqueProperties, CoverPiecesDoNotOverlap, ()) {
    Image image = *gen_solid_shape();
    const int min_area = *rc::gen::inRange(1, 64);
    Rect all = image.view().bounds();
    auto pieces = generate_opaque_polygons(image.view(), all, options(OpaqueMethod::cover, Filter::nearest, min_area, 64));
    RC_TAG(pieces.size() > 1 ? "several pieces" : "at most one");
    std::int64_t each = 0;
    for (const auto& p : pieces) each += count_centre_covered_opaque_texels(image.view(), all, {p});
    RC_ASSERT(each == count_centre_covered_opaque_texels(image.view(), all, pieces));
}

// With pieces of any size allowed, cover reaches the centres of every
// texel that some convex piece of its stack could: at least as many as the
// paper's quads at the same limits, in texel centres.
RC_GTEST_PROP(OpaqueProperties, CoverCoversAtLeastThePaperInCentres, ()) {
    Image image = *gen_solid_shape();
    Rect all = image.view().bounds();
    auto paper = generate_opaque_polygons(image.view(), all, options(OpaqueMethod::paper, Filter::nearest, 1, 4));
    auto cover = generate_opaque_polygons(image.view(), all, options(OpaqueMethod::cover, Filter::nearest, 1, 64));
    const std::int64_t p = count_centre_covered_opaque_texels(image.view(), all, paper);
    const std::int64_t c = count_centre_covered_opaque_texels(image.view(), all, cover);
    RC_TAG(c > p ? "more" : "as many");
    RC_ASSERT(c >= p);
}

TEST(OpaqueCover, ASolidImageIsOnePieceOverEveryCentre) {
    // (A 1x1 image's piece, 7/8 texel square, is under min_area 1.)
    for (auto [w, h] : {std::pair{2, 1}, {3, 1}, {20, 7}, {64, 64}}) {
        Image image;
        image.width = w, image.height = h;
        image.rgba.assign(std::size_t(w) * h * 4, 255);
        auto pieces = generate_opaque_polygons(image.view(), image.view().bounds(),
                                               options(OpaqueMethod::cover, Filter::nearest, 1, 4));
        ASSERT_EQ(pieces.size(), 1u) << w << "x" << h;
        const Polygon expected{{1.0 / 16, 1.0 / 16}, {w - 1.0 / 16, 1.0 / 16}, {w - 1.0 / 16, h - 1.0 / 16}, {1.0 / 16, h - 1.0 / 16}};
        EXPECT_EQ(pieces[0], expected);
        EXPECT_EQ(count_centre_covered_opaque_texels(image.view(), image.view().bounds(), pieces), std::int64_t(w) * h);
        EXPECT_EQ(count_opaque_violations(image.view(), image.view().bounds(), pieces, Filter::nearest), 0);
    }
}

TEST(OpaqueCover, ARingSplitsIntoTopArmsAndBottom) {
    // 12x12 opaque with a 4x4 hole in the middle: four stacks, one piece each.
    Image image;
    image.width = image.height = 12;
    image.rgba.assign(12 * 12 * 4, 255);
    for (int y = 4; y < 8; ++y)
        for (int x = 4; x < 8; ++x) image.rgba[std::size_t(y * 12 + x) * 4 + 3] = 0;
    auto pieces = generate_opaque_polygons(image.view(), image.view().bounds(),
                                           options(OpaqueMethod::cover, Filter::nearest, 1, 64));
    EXPECT_EQ(pieces.size(), 4u);
    EXPECT_EQ(count_centre_covered_opaque_texels(image.view(), image.view().bounds(), pieces), 12 * 12 - 16);
    EXPECT_EQ(count_opaque_violations(image.view(), image.view().bounds(), pieces, Filter::nearest), 0);
    // max_polygons keeps the largest: the top and bottom (48 texels each).
    pieces = generate_opaque_polygons(image.view(), image.view().bounds(),
                                      options(OpaqueMethod::cover, Filter::nearest, 1, 2));
    EXPECT_EQ(count_centre_covered_opaque_texels(image.view(), image.view().bounds(), pieces), 2 * 48);
    // min_area: pieces under 40 texels (the arms hold 16) do not pay.
    pieces = generate_opaque_polygons(image.view(), image.view().bounds(),
                                      options(OpaqueMethod::cover, Filter::nearest, 40, 64));
    EXPECT_EQ(pieces.size(), 2u);
}

TEST(OpaqueCover, ADiscFollowsItsOutlineAsFarAsPieceCostAllows) {
    // A disc of radius 30: with cheap pieces cover follows the outline
    // (more pieces, more centres); with dear ones it takes fewer.
    Image image;
    image.width = image.height = 64;
    image.rgba.assign(64 * 64 * 4, 0);
    std::int64_t opaque = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            if ((x - 31.5) * (x - 31.5) + (y - 31.5) * (y - 31.5) <= 30.0 * 30.0)
                image.rgba[std::size_t(y * 64 + x) * 4 + 3] = 255, ++opaque;
    const Rect all = image.view().bounds();
    auto cheap = generate_opaque_polygons(image.view(), all, options(OpaqueMethod::cover, Filter::nearest, 4, 64));
    auto dear = generate_opaque_polygons(image.view(), all, options(OpaqueMethod::cover, Filter::nearest, 256, 64));
    auto fast = generate_opaque_polygons(image.view(), all, options(OpaqueMethod::fast, Filter::nearest, 64, 4));
    const auto c = count_centre_covered_opaque_texels(image.view(), all, cheap);
    const auto d = count_centre_covered_opaque_texels(image.view(), all, dear);
    const auto f = count_centre_covered_opaque_texels(image.view(), all, fast);
    EXPECT_GT(cheap.size(), dear.size());
    EXPECT_GE(c, d);
    EXPECT_GT(c, f);
    EXPECT_GT(double(c) / double(opaque), 0.95); // 0.963 today
    EXPECT_EQ(count_opaque_violations(image.view(), all, cheap, Filter::nearest), 0);
    EXPECT_EQ(count_opaque_violations(image.view(), all, dear, Filter::nearest), 0);
}

// ---- The exact arithmetic the fast search's bounds rest on.

TEST(OpaqueArithmetic, FloorSumMatchesTheLoop) {
    std::mt19937 rng(3);
    for (int k = 0; k < 2000; ++k) {
        std::int64_t n = rng() % 60, m = 1 + rng() % 40, a = std::int64_t(rng() % 200) - 100,
                     b = std::int64_t(rng() % 200) - 100, sum = 0;
        for (std::int64_t i = 0; i < n; ++i) sum += floor_div(a * i + b, m);
        ASSERT_EQ(opaque_detail::floor_sum(n, m, a, b), sum) << n << " " << m << " " << a << " " << b;
    }
}

TEST(OpaqueArithmetic, CoveredColumnsMatchTheChecker) {
    // covered_columns at scale 2 and count_covered_opaque_texels agree.
    std::vector<std::string> rows(12, std::string(12, '#'));
    Image image;
    image.width = image.height = 12;
    image.rgba.assign(12 * 12 * 4, 255);
    std::mt19937 rng(9);
    for (int k = 0; k < 500; ++k) {
        opaque_detail::HalfPolygon tri{{std::int64_t(rng() % 25), 0}, {24, std::int64_t(rng() % 25)}, {0, 24}};
        std::int64_t n = 0;
        for (int y = 0; y < 12; ++y) {
            std::int64_t lo, hi;
            opaque_detail::covered_columns(tri, y, lo, hi);
            n += std::max<std::int64_t>(0, std::min<std::int64_t>(hi, 12) - std::max<std::int64_t>(lo, 0));
        }
        Polygon p = opaque_detail::to_polygon(tri, {0, 0, 12, 12});
        if (signed_area(p) <= 0) continue;
        ASSERT_EQ(count_covered_opaque_texels(image.view(), image.view().bounds(), {p}), n);
    }
}

TEST(OpaqueArithmetic, CentreCoverageMatchesTheChecker) {
    // centre_covered_texels (what fast compares, issue 25) and
    // count_centre_covered_opaque_texels agree on random triangles, two at
    // a time (centres under both count once; centres on an edge do not count).
    Image image;
    image.width = image.height = 12;
    image.rgba.assign(12 * 12 * 4, 255);
    std::mt19937 rng(10);
    int nonzero = 0;
    for (int k = 0; k < 500; ++k) {
        auto triangle = [&] {
            return opaque_detail::HalfPolygon{{std::int64_t(rng() % 25), 0}, {24, std::int64_t(rng() % 25)}, {0, 24}};
        };
        const std::vector<opaque_detail::HalfPolygon> two{triangle(), triangle()};
        std::vector<Polygon> polygons;
        for (const auto& t : two) polygons.push_back(opaque_detail::to_polygon(t, {0, 0, 12, 12}));
        const std::int64_t n = opaque_detail::centre_covered_texels(two);
        nonzero += n > 0;
        ASSERT_EQ(count_centre_covered_opaque_texels(image.view(), image.view().bounds(), polygons), n) << k;
    }
    EXPECT_GT(nonzero, 400);
    // A square through the outer centres of a 4x4 image: the inner 4.
    image.width = image.height = 4;
    image.rgba.assign(4 * 4 * 4, 255);
    EXPECT_EQ(count_centre_covered_opaque_texels(image.view(), image.view().bounds(), {{{0.5, 0.5}, {3.5, 0.5}, {3.5, 3.5}, {0.5, 3.5}}}), 4);
}

TEST(OpaqueArithmetic, ConvexValidMatchesTheChecker) {
    // The growth search accepts a polygon only through convex_valid; it must
    // agree with the analyzer on random convex polygons (hulls of random
    // half-grid points, edges on grid lines included) over random masks.
    std::mt19937 rng(11);
    int valid = 0;
    for (int k = 0; k < 4000; ++k) {
        const int w = 4 + int(rng() % 9), h = 4 + int(rng() % 9);
        Image image;
        image.width = w, image.height = h;
        image.rgba.assign(std::size_t(w) * h * 4, 255);
        for (int i = 0, holes = int(rng() % 4); i < holes; ++i)
            image.rgba[(std::size_t(rng() % h) * w + rng() % w) * 4 + 3] = std::uint8_t(rng() % 2 ? 0 : 200);
        // A hull of 3..6 points (Andrew's monotone chain), clockwise with y down.
        std::vector<opaque_detail::HalfPoint> pts;
        for (int i = 0, n = 3 + int(rng() % 4); i < n; ++i)
            pts.push_back({std::int64_t(rng() % (2 * w + 3)) - 1, std::int64_t(rng() % (2 * h + 3)) - 1});
        opaque_detail::HalfPolygon hull = test::convex_hull(
            pts, [](auto o, auto a, auto b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); });
        if (hull.size() < 3) continue;
        std::reverse(hull.begin(), hull.end()); // counter-clockwise in y-up terms is clockwise on screen
        Polygon p = opaque_detail::to_polygon(hull, {0, 0, w, h});
        if (signed_area(p) <= 0) std::reverse(hull.begin(), hull.end()), p = opaque_detail::to_polygon(hull, {0, 0, w, h});
        ASSERT_GT(signed_area(p), 0);
        const opaque_detail::SafeGrid grid(opaque_mask(image.view(), image.view().bounds()));
        std::int64_t work = 0;
        const bool ok = opaque_detail::convex_valid(hull, grid, work);
        ASSERT_EQ(ok, count_opaque_violations(image.view(), image.view().bounds(), {p}, Filter::nearest) == 0) << k;
        valid += ok;
    }
    EXPECT_GT(valid, 200);
}

} // namespace
} // namespace depthcull
