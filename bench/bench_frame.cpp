// Frame assembly of moving sprites (depthcull/frame.h, issue 23): N sprites
// over 32 pictures (4 textures of 8 atlas frames), rotated, scaled 0.25-2,
// overlapping, a quarter translucent, moving every frame across a
// 1920x1080 screen (deterministic seed). Budgets on one core: 10,000
// sprites within 1 ms a frame, 100,000 within 10 ms. Analyses are
// synthetic (octagon boundary, quad opaque core, as bench_scene) so only
// assembly is measured; the frame's buffers are reused (no allocation
// after the first frame: FrameAssembler.FramesAllocateNothingAfterWarmUp).
// Two uses: fully dynamic frames (BM_AssembleFrame) and the sprites at an
// insertion point between the layers of a static scene (BM_AssembleAt: a
// background of 2,000 tiles, the point, 500 foreground decorations).
// Times are process CPU time per frame (assembly is single-threaded):
//   LP_NUM_THREADS=1 build/bench/bench_frame --benchmark_repetitions=5
#include <cmath>
#include <memory>
#include <random>

#include <benchmark/benchmark.h>

#include "depthcull/frame.h"
#include "depthcull/scene.h"

namespace {

using namespace depthcull;

struct Setup {
    std::vector<ImageAnalysis> analyses;
    FrameAssembler assembler;
    std::vector<Sprite> sprites;
    std::vector<double> speed;
};

std::unique_ptr<Setup> make_setup(int n, std::uint64_t seed) {
    auto s = std::make_unique<Setup>();
    std::mt19937_64 rng(seed);
    s->analyses.reserve(32);
    std::vector<int> ids;
    for (int texture = 0; texture < 4; ++texture)
        for (int frame = 0; frame < 8; ++frame) {
            const int w = 32 + 8 * texture, h = 32 + 4 * frame;
            ImageAnalysis a;
            a.rect = {frame * 64, 0, w, h};
            const double x0 = a.rect.x, x = w, y = h, cx = std::floor(x / 4), cy = std::floor(y / 4);
            a.boundary = {{{x0 + cx, 0}, {x0 + x - cx, 0}, {x0 + x, cy}, {x0 + x, y - cy}, {x0 + x - cx, y}, {x0 + cx, y}, {x0, y - cy}, {x0, cy}}};
            a.opaque = {{{x0 + cx, cy}, {x0 + x - cx, cy}, {x0 + x - cx, y - cy}, {x0 + cx, y - cy}}};
            a.stats.nontransparent_texels = std::int64_t(w) * h;
            a.stats.opaque_covered_texels = std::int64_t(x - 2 * cx) * std::int64_t(y - 2 * cy);
            s->analyses.push_back(a);
            int id = -1;
            s->assembler.add_image({texture, 512, 128, a.rect, &s->analyses.back()}, &id);
            ids.push_back(id);
        }
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < n; ++i) {
        Sprite sp;
        sp.image = ids[rng() % ids.size()];
        const double scale = 0.25 + 1.75 * u(rng), angle = 6.2831853 * u(rng);
        sp.transform = {scale * std::cos(angle), scale * std::sin(angle), -scale * std::sin(angle), scale * std::cos(angle),
                        1920 * u(rng), 1080 * u(rng)};
        if (rng() % 4 == 0) sp.color = {1, 1, 1, 0.7f};
        s->sprites.push_back(sp);
        s->speed.push_back(4 * u(rng) - 2);
    }
    return s;
}

void BM_AssembleFrame(benchmark::State& state) {
    const int n = int(state.range(0));
    auto s = make_setup(n, 23);
    AssembledFrame frame;
    s->assembler.reserve(std::size_t(n), &frame);
    const Viewport view{0, 0, 1920, 1080};
    for (auto _ : state) {
        // Move every sprite (the game's part of a frame: not timed).
        state.PauseTiming();
        for (std::size_t i = 0; i < s->sprites.size(); ++i) {
            auto& m = s->sprites[i].transform;
            m[4] += s->speed[i], m[5] += 0.5 * s->speed[i];
            m[4] += m[4] < 0 ? 1920 : m[4] >= 1920 ? -1920 : 0;
            m[5] += m[5] < 0 ? 1080 : m[5] >= 1080 ? -1080 : 0;
        }
        state.ResumeTiming();
        benchmark::DoNotOptimize(s->assembler.assemble(s->sprites, view, &frame));
    }
    state.counters["draws"] = double(frame.stats.draw_calls);
    state.counters["blend_batches"] = double(frame.stats.blend_batches);
    state.counters["triangles"] = double(frame.stats.triangles);
    state.counters["over_budget"] = double(frame.stats.over_budget);
    state.SetItemsProcessed(std::int64_t(state.iterations()) * n);
}
BENCHMARK(BM_AssembleFrame)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

void BM_AssembleAt(benchmark::State& state) {
    const int n = int(state.range(0));
    auto s = make_setup(n, 23);
    // The static scene: a background of 64x64 tiles (picture 0 scaled up
    // 2x, opaque core), the game layer's insertion point, then foreground
    // decorations (turned pictures).
    Scene scene;
    scene.viewport = {0, 0, 1920, 1080};
    scene.images.push_back({"atlas", "atlas.png", 512, 128});
    std::vector<const ImageAnalysis*> analyses;
    std::mt19937_64 rng(7);
    for (int y = 0; y < 1080; y += 64)
        for (int x = 0; x < 1920 + 64 * 32; x += 64) {
            Element e;
            e.rect = s->analyses[0].rect;
            e.transform = {2, 0, 0, 2, double(x % 1920), double(y)};
            scene.elements.push_back(e);
            analyses.push_back(&s->analyses[0]);
        }
    const std::size_t point = scene.elements.size();
    for (int i = 0; i < 500; ++i) {
        const std::size_t k = rng() % s->analyses.size();
        Element e;
        e.rect = s->analyses[k].rect;
        const double a = double(rng() % 628) / 100;
        e.transform = {std::cos(a), std::sin(a), -std::sin(a), std::cos(a), double(rng() % 1920), double(rng() % 1080)};
        scene.elements.push_back(e);
        analyses.push_back(&s->analyses[k]);
    }
    ReconstructOptions options;
    options.insertion_points = {{point, n}};
    SceneMeshes meshes;
    if (reconstruct_scene(scene, analyses, options, &meshes) != ReconstructStatus::ok) {
        state.SkipWithError("reconstruction failed");
        return;
    }
    AssembledFrame frame;
    s->assembler.reserve(std::size_t(n), &frame);
    const Viewport view{0, 0, 1920, 1080};
    const std::span<const Sprite> lists[1] = {s->sprites};
    for (auto _ : state) {
        state.PauseTiming();
        for (std::size_t i = 0; i < s->sprites.size(); ++i) {
            auto& m = s->sprites[i].transform;
            m[4] += s->speed[i], m[5] += 0.5 * s->speed[i];
            m[4] += m[4] < 0 ? 1920 : m[4] >= 1920 ? -1920 : 0;
            m[5] += m[5] < 0 ? 1080 : m[5] >= 1080 ? -1080 : 0;
        }
        state.ResumeTiming();
        benchmark::DoNotOptimize(s->assembler.assemble_at(meshes, lists, view, &frame));
    }
    state.counters["draws"] = double(frame.stats.draw_calls);
    state.counters["static_draws"] = double(meshes.draws.size());
    state.counters["triangles"] = double(frame.stats.triangles);
    state.SetItemsProcessed(std::int64_t(state.iterations()) * n);
}
BENCHMARK(BM_AssembleAt)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

} // namespace

BENCHMARK_MAIN();
