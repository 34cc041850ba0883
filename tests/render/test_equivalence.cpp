// Metamorphic check of the whole pipeline: random scenes (seeded, so
// failures reproduce) analyzed and reconstructed for real, drawn meshes
// only and optimized, must draw like overpaint. Placements mix what games
// do (half-pixel positions, quarter turns, flips, x0.5 / x2 scales) with
// arbitrary angles and scales.
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <cstdlib>
#include <random>

#include "depthcull/render.h"
#include "render_scenes.h"
#include "shared_renderer.h"

namespace depthcull {
namespace {

test::RenderScene random_scene(unsigned seed, Filter filter) {
    std::mt19937 rng(seed);
    auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
    auto pick = [&](int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); };
    test::RenderScene rs;
    rs.scene.viewport = {-8, 4, 96, 72};
    rs.scene.filter = filter;
    rs.add_image(test::test_sprite(), {});
    rs.add_image(test::ascii_image({
                     "##..........##",
                     "##...+##+...##",
                     "....+####+....",
                     "....######....",
                     "....+####+....",
                     "##...+##+...##",
                     "##..........##",
                 }),
                 {});
    rs.add_image(test::ascii_image({"#####", "#####", "#####", "#####"}), {});
    // Frames a column apart, as atlases for bilinear filtering are packed:
    // without padding, filtering at a frame's edge mixes in its neighbour's
    // texels, which no analysis of the frame alone can know about.
    const int page = rs.add_image(test::ascii_image({
                                      "########.....++++",
                                      "########....+##++",
                                      "##....##...+####+",
                                      "##....##...+####+",
                                      "########....+##+.",
                                      "########.....++..",
                                  }),
                                  {});
    const int count = 30 + pick(20);
    for (int i = 0; i < count; ++i) {
        const int image = pick(4);
        double scale = std::array<double, 5>{0.5, 1, 1, 2, uniform(0.4, 3)}[std::size_t(pick(5))];
        double degrees = std::array<double, 5>{0, 0, 90, 180, uniform(0, 360)}[std::size_t(pick(5))];
        double x = std::round(uniform(-20, 90) * 2) / 2, y = std::round(uniform(-10, 80) * 4) / 4;
        if (pick(4) == 0) {
            x = uniform(-20, 90);
            y = uniform(-10, 80);
        }
        auto m = test::rotation(degrees, x, y, scale);
        if (pick(4) == 0) { // mirror in x
            m[0] = -m[0];
            m[1] = -m[1];
        }
        const Blend blend = std::array<Blend, 6>{Blend::alpha, Blend::alpha, Blend::alpha, Blend::add, Blend::multiply, Blend::opaque}
            [std::size_t(pick(6))];
        std::array<float, 4> color{1, 1, 1, 1};
        if (pick(4) == 0) color = {float(uniform(0.3, 1)), float(uniform(0.3, 1)), float(uniform(0.3, 1)), pick(2) ? 1.0f : 0.6f};
        Element& e = rs.add(image, m, blend, color);
        if (image == page) e.rect = pick(2) ? Rect{0, 0, 8, 6} : Rect{9, 0, 8, 6};
    }
    return rs;
}

void check(unsigned seed, Filter filter) {
    std::string why;
    bool no_context = false;
    render::GlRenderer* r = test::shared_renderer(&why, &no_context);
    if (!r && no_context) GTEST_SKIP() << why;
    if (!r) FAIL() << why;
    SCOPED_TRACE("seed " + std::to_string(seed));
    auto rs = random_scene(seed, filter);
    AnalyzeOptions analyze;
    analyze.filter = filter;
    SceneAnalysis analysis; // one per element
    for (const Element& e : rs.scene.elements) {
        analysis.of_element.push_back(std::uint32_t(analysis.images.size()));
        analysis.images.push_back(analyze_image(rs.images[std::size_t(e.image)].view(), e.rect, analyze));
    }
    render::MeasureOptions options;
    options.frames = 0;
    auto m = render::measure_scene(*r, rs.scene, rs.views(), analysis, options);
    for (const auto& mode : m.modes) {
        SCOPED_TRACE(render::mode_name(mode.mode));
        if (filter == Filter::nearest) {
            // Every element samples through its one texel map in every mode,
            // so nothing, not even a pixel centre on a texel edge, may differ.
            EXPECT_EQ(mode.diff.pixels_differ, 0) << mode.causes.near_edges << " near triangle or texel edges, "
                                                  << mode.causes.elsewhere << " elsewhere, largest channel difference "
                                                  << mode.diff.max_channel_diff;
        } else {
            EXPECT_EQ(mode.causes.elsewhere, 0) << mode.diff.pixels_differ << " pixels differ, largest channel difference "
                                                << mode.diff.max_channel_diff;
            // Bilinear filtering at polygon edges: rare by nature (about 1 in
            // 10000 pixels here); more means geometry that hugs pixel centres.
            EXPECT_LE(mode.causes.near_edges, 8);
            ::testing::Test::RecordProperty(std::string("near_edges_") + render::mode_name(mode.mode) + "_" + std::to_string(seed),
                                            int(mode.causes.near_edges));
        }
        EXPECT_LE(m.ideal_overdraw, mode.overdraw);
    }
}

// Issue 21: a boundary polygon with one sharp notch (the bundled "moons"
// sprite's outline) lost its whole texel skirt, so GL's snapping missed a
// pixel centre 0.0003 pixel inside its far edge u = 47 (pixel 349, 92
// here, texel 46 non-transparent): the optimized frame showed the ground
// where overpaint blended the texel. The skirt now ends short at the notch
// and stays on every other edge.
TEST(Equivalence, SharpNotchKeepsTheSkirtOfEveryOtherEdge) {
    std::string why;
    bool no_context = false;
    render::GlRenderer* r = test::shared_renderer(&why, &no_context);
    if (!r && no_context) GTEST_SKIP() << why;
    if (!r) FAIL() << why;
    test::RenderScene rs;
    rs.scene.viewport = {0, 0, 480, 360};
    const int ground = rs.add_image(test::ascii_image({"####", "####", "####"}), {0, 0, 4, 3});
    std::vector<std::string> rows(24, std::string(48, '.'));
    for (int y = 11; y < 17; ++y)
        for (int x = 40; x < 47; ++x) rows[std::size_t(y)][std::size_t(x)] = '1'; // alpha 25
    const int sprite = rs.add_image(test::ascii_image(rows), {});
    rs.add(ground, {120, 0, 0, 120, 0, 0}, Blend::opaque);
    rs.add(sprite, {-0.321685, -1.766569, 1.766569, -0.321685, 341.211, 179.791});
    SceneAnalysis analysis;
    analysis.of_element = {0, 1};
    analysis.images.push_back(analyze_image(rs.images[0].view(), rs.scene.elements[0].rect, {}));
    ImageAnalysis notched;
    notched.rect = rs.scene.elements[1].rect;
    // Clockwise (y down); the notch at (34, 10) turns by about 162 degrees.
    notched.boundary = {{{25, 7}, {31, 1}, {41, 1}, {46, 6}, {34, 10}, {47, 10}, {47, 17}, {41, 23}, {31, 23}, {25, 17}}};
    analysis.images.push_back(notched);
    render::MeasureOptions options;
    options.frames = 0;
    const auto m = render::measure_scene(*r, rs.scene, rs.views(), analysis, options);
    for (const auto& mode : m.modes) {
        SCOPED_TRACE(render::mode_name(mode.mode));
        EXPECT_EQ(mode.diff.pixels_differ, 0) << mode.causes.near_edges << " near triangle or texel edges";
    }
}

// DEPTHCULL_EQUIVALENCE_SEEDS=N checks N scenes instead of the default
// (a longer local hunt for rare differences; CI keeps the default).
unsigned seed_count(unsigned fallback) {
    const char* text = std::getenv("DEPTHCULL_EQUIVALENCE_SEEDS");
    const long n = text ? std::strtol(text, nullptr, 10) : 0;
    return n > 0 ? unsigned(n) : fallback;
}

TEST(Equivalence, RandomScenesNearest) {
    const unsigned count = seed_count(12);
    for (unsigned seed = 1; seed <= count; ++seed) check(seed, Filter::nearest);
}

TEST(Equivalence, RandomScenesLinear) {
    for (unsigned seed = 101; seed <= 106; ++seed) check(seed, Filter::linear);
}

// Issue 21 point 3: level layouts with most sprites scaled down (0.1 ..
// 3) and turned by arbitrary angles at arbitrary positions. The texel
// skirt (ReconstructOptions::texel_margin) must not stack on the coverage
// skirt the proof draws with: overpaint's frame exactly, every pixel.
RC_GTEST_PROP(Equivalence, TurnedSpritesScaledDownAndUpDrawLikeOverpaint, ()) {
    std::string why;
    bool no_context = false;
    render::GlRenderer* r = test::shared_renderer(&why, &no_context);
    if (!r) {
        RC_SUCCEED("no GL renderer: " + why); // Equivalence.RandomScenesNearest reports it
        return;
    }
    test::RenderScene rs;
    rs.scene.viewport = {-8, 4, 96, 72};
    rs.add_image(test::test_sprite(), {});
    rs.add_image(test::ascii_image({"..++++..", ".+####+.", "+######+", "+######+", ".+####+.", "..++++.."}), {});
    const int page = rs.add_image(test::ascii_image({
                                      "########.....++++",
                                      "########....+##++",
                                      "##....##...+####+",
                                      "##....##...+####+",
                                      "########....+##+.",
                                      "########.....++..",
                                  }),
                                  {});
    const int count = *rc::gen::inRange(10, 40);
    for (int i = 0; i < count; ++i) {
        const int image = *rc::gen::inRange(0, 3);
        const double scale = *rc::gen::inRange(100, 3001) / 1000.0;
        const double degrees = *rc::gen::inRange(0, 36000) / 100.0;
        const double x = *rc::gen::inRange(-20000, 90000) / 1000.0, y = *rc::gen::inRange(-10000, 80000) / 1000.0;
        auto m = test::rotation(degrees, x, y, scale);
        if (*rc::gen::inRange(0, 4) == 0) m[0] = -m[0], m[1] = -m[1]; // mirrored
        const Blend blend = *rc::gen::element(Blend::alpha, Blend::alpha, Blend::add, Blend::multiply, Blend::opaque);
        const std::array<float, 4> color = *rc::gen::element(std::array<float, 4>{1, 1, 1, 1}, std::array<float, 4>{1, 1, 1, 0.5f},
                                                             std::array<float, 4>{0.5f, 1, 0.75f, 1});
        Element& e = rs.add(image, m, blend, color);
        if (image == page) e.rect = *rc::gen::element(Rect{0, 0, 8, 6}, Rect{9, 0, 8, 6});
    }
    SceneAnalysis analysis; // one per element
    for (const Element& e : rs.scene.elements) {
        analysis.of_element.push_back(std::uint32_t(analysis.images.size()));
        analysis.images.push_back(analyze_image(rs.images[std::size_t(e.image)].view(), e.rect, {}));
    }
    render::MeasureOptions options;
    options.frames = 0;
    const auto m = render::measure_scene(*r, rs.scene, rs.views(), analysis, options);
    for (const auto& mode : m.modes) {
        RC_LOG() << render::mode_name(mode.mode) << ": " << mode.diff.pixels_differ << " pixels differ, " << mode.causes.near_edges
                 << " near edges\n";
        RC_ASSERT(mode.diff.pixels_differ == 0);
    }
}

} // namespace
} // namespace depthcull
