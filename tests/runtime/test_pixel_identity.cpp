// Pixel identity in a plain renderer (ReconstructOptions::texel_margin):
// depthcull::runtime draws meshes only and optimized exactly like its own
// overpaint frame, nearest filtering, on the bundled example, random
// scenes and every corpus camera of scripts/bench-corpus. The only
// differences allowed are pixels whose centre lies exactly on a texel edge
// (render::count_off_texel_edges tells them apart: the exact texel
// position of the centre, from the element's map, is integral).
#include <gtest/gtest.h>

#include <random>

#include "../render/render_scenes.h"
#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "runtime_host.h"
#include "testing/corpus.h"

namespace depthcull {
namespace {

void expect_identical(test::RuntimeHost& h, const Scene& scene, const std::vector<ImageView>& images,
                      const SceneAnalysis& analyses, const std::string& label) {
    render::MeasureOptions options;
    options.frames = 0;
    render::RuntimeMeasurement m = render::measure_runtime(*h.host, scene, images, analyses, options);
    for (const auto& mode : m.modes) {
        EXPECT_EQ(mode.off_texel_edges, 0) << label << " " << render::mode_name(mode.mode) << ": " << mode.diff.pixels_differ
                                           << " pixels differ, " << mode.off_texel_edges << " off texel edges";
        if (mode.diff.pixels_differ)
            std::printf("%s %s: %lld pixels differ, all on texel edges\n", label.c_str(), render::mode_name(mode.mode),
                        (long long)mode.diff.pixels_differ);
    }
}

void expect_identical(test::RuntimeHost& h, const pipeline::PreparedScene& p, const std::string& label) {
    expect_identical(h, p.scene, p.views(), p.analysis, label);
}

class PixelIdentity : public testing::TestWithParam<render::GlApi> {};

TEST_P(PixelIdentity, BundledExample) {
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    expect_identical(*h, pipeline::prepare_scene(test::source_path("examples/meadow.json"), {}), "meadow");
}

// Sprites with transparent margins, translucent rims and opaque cores,
// turned as games do (quarter turns, flips, x1/8 .. x3 scales) and at
// arbitrary angles, at arbitrary positions.
TEST_P(PixelIdentity, RandomScenes) {
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    for (unsigned seed = 1; seed <= 8; ++seed) {
        std::mt19937 rng(seed);
        auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
        auto pick = [&](int n) { return std::uniform_int_distribution<int>(0, n - 1)(rng); };
        test::RenderScene rs;
        rs.scene.viewport = {-8, 4, 120, 90};
        rs.add_image(test::test_sprite(), {});
        rs.add_image(test::ascii_image({"..++++..", ".+####+.", "+######+", "+######+", ".+####+.", "..++++.."}), {});
        rs.add_image(test::ascii_image({"####", "####", "####"}), {});
        for (int i = 0; i < 40; ++i) {
            const double scale = std::array<double, 6>{0.125, 0.5, 1, 1, 2, uniform(0.3, 3)}[std::size_t(pick(6))];
            const double degrees = std::array<double, 5>{0, 0, 90, 180, uniform(0, 360)}[std::size_t(pick(5))];
            // Off the grid: a pixel centre then lies exactly on a texel edge
            // only by chance (about once in 2^15 pixels), so nearly every
            // difference would be a real one.
            const double x = uniform(-10, 110), y = uniform(0, 90);
            auto m = test::rotation(degrees, x, y, scale);
            if (pick(4) == 0) m[0] = -m[0], m[1] = -m[1];
            const Blend blend = std::array<Blend, 5>{Blend::alpha, Blend::alpha, Blend::add, Blend::multiply, Blend::opaque}[std::size_t(pick(5))];
            std::array<float, 4> color{1, 1, 1, 1};
            if (pick(4) == 0) color = {float(uniform(0.3, 1)), float(uniform(0.3, 1)), float(uniform(0.3, 1)), pick(2) ? 1.0f : 0.6f};
            rs.add(pick(3), m, blend, color);
        }
        SceneAnalysis analysis; // one per element
        for (const Element& e : rs.scene.elements) {
            analysis.of_element.push_back(std::uint32_t(analysis.images.size()));
            analysis.images.push_back(analyze_image(rs.images[std::size_t(e.image)].view(), e.rect, {}));
        }
        expect_identical(*h, rs.scene, rs.views(), analysis, "seed " + std::to_string(seed));
    }
}

// The cameras of scripts/bench-corpus: each Tiled map's centre and quarter
// points, 1024x768 (smaller maps whole).
TEST_P(PixelIdentity, EveryCorpusCamera) {
    // One target is enough here (about a minute each): the shaders differ
    // only in their version line, and the other tests cover both.
    if (GetParam() == render::GlApi::gles) GTEST_SKIP() << "corpus cameras are drawn on desktop GL only";
    DEPTHCULL_RUNTIME_HOST(h, GetParam());
    int cameras = 0;
    for (const char* package : {"tiled", "btanks-data"}) {
        if (std::string why = test::corpus_missing(package); !why.empty()) GTEST_SKIP() << why;
        std::vector<std::string> maps = test::corpus_files(package, ".tmx");
        for (const std::string& p : test::corpus_files(package, ".tmx.gz")) maps.push_back(p);
        for (const std::string& path : maps) {
            pipeline::PreparedScene p;
            try {
                pipeline::PrepareOptions options;
                options.cache_dir = pipeline::default_cache_dir();
                p = pipeline::prepare_scene(path, options);
            } catch (const io::Error&) {
                continue; // maps depthcull refuses (hexagonal, staggered) are listed by bench-corpus
            }
            const Viewport whole = p.scene.viewport;
            const int w = std::min(1024, whole.width), hgt = std::min(768, whole.height);
            std::vector<std::pair<double, double>> seen;
            for (double f : {0.5, 0.25, 0.75}) {
                const double x = whole.x + std::min(std::max(std::round(f * whole.width - w / 2.0), 0.0), double(whole.width - w));
                const double y = whole.y + std::min(std::max(std::round(f * whole.height - hgt / 2.0), 0.0), double(whole.height - hgt));
                if (std::find(seen.begin(), seen.end(), std::pair{x, y}) != seen.end()) continue;
                seen.emplace_back(x, y);
                p.scene.viewport = {x, y, w, hgt};
                expect_identical(*h, p, path + "@" + std::to_string(int(x)) + "," + std::to_string(int(y)));
                ++cameras;
            }
        }
    }
    std::printf("%d corpus cameras\n", cameras);
}

INSTANTIATE_TEST_SUITE_P(Targets, PixelIdentity, testing::Values(render::GlApi::desktop, render::GlApi::gles),
                         [](const auto& info) { return info.param == render::GlApi::gles ? "es30" : "gl33"; });

} // namespace
} // namespace depthcull
