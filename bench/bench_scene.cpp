// Reconstruction (paper 2.3) on synthetic scenes: N elements over a few
// hundred images, rotated and scaled, about a dozen overlaps each. Time
// should grow near-linearly with N (issue 4: 100k elements well under a
// second on one core). Analyses are synthetic (octagon boundary, quad
// opaque) so only reconstruction is measured.
#include <cmath>
#include <memory>
#include <random>

#include <benchmark/benchmark.h>

#include "depthcull/cost.h"
#include "depthcull/overdraw.h"
#include "depthcull/scene.h"

namespace {

using namespace depthcull;

struct Synthetic {
    Scene scene;
    std::vector<std::unique_ptr<ImageAnalysis>> owned;
    std::vector<const ImageAnalysis*> analyses;
};

Synthetic make_scene(int n, int images, std::uint64_t seed) {
    Synthetic s;
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<int> side(16, 96);
    std::vector<const ImageAnalysis*> per_image;
    for (int k = 0; k < images; ++k) {
        int w = side(rng), h = side(rng);
        s.scene.images.push_back({"img" + std::to_string(k), "img" + std::to_string(k) + ".png", w, h});
        auto a = std::make_unique<ImageAnalysis>();
        a->rect = {0, 0, w, h};
        double x = w, y = h, cx = std::floor(x / 4), cy = std::floor(y / 4);
        a->boundary = {{{cx, 0}, {x - cx, 0}, {x, cy}, {x, y - cy}, {x - cx, y}, {cx, y}, {0, y - cy}, {0, cy}}};
        a->opaque = {{{cx, cy}, {x - cx, cy}, {x - cx, y - cy}, {cx, y - cy}}};
        per_image.push_back(a.get());
        s.owned.push_back(std::move(a));
    }
    // World sized for ~12 overlaps per element (average sprite ~56 px).
    const double world = std::sqrt(double(n) * 56 * 56 / 3.0);
    std::uniform_real_distribution<double> pos(0, world), angle(0, 6.2831853), scale(0.5, 1.5);
    std::uniform_int_distribution<int> pick(0, images - 1);
    // Images come in runs (a level's tiles, a cluster of props), as in games.
    int current = pick(rng);
    for (int i = 0; i < n; ++i) {
        if (rng() % 8 == 0) current = pick(rng);
        Element e;
        e.image = current;
        e.rect = {0, 0, s.scene.images[std::size_t(current)].width, s.scene.images[std::size_t(current)].height};
        double r = angle(rng), sc = scale(rng);
        e.transform = {sc * std::cos(r), sc * std::sin(r), -sc * std::sin(r), sc * std::cos(r), pos(rng), pos(rng)};
        s.scene.elements.push_back(e);
        s.analyses.push_back(per_image[std::size_t(current)]);
    }
    s.scene.viewport = {0, 0, 1024, 768};
    return s;
}

void report(benchmark::State& state, const SceneMeshes& m) {
    state.counters["elements"] = double(m.stats.elements);
    state.counters["edges"] = double(m.stats.graph_edges);
    state.counters["draws"] = double(m.stats.draw_calls);
    state.counters["levels"] = double(m.stats.depth_levels);
    state.counters["elements/s"] = benchmark::Counter(double(m.stats.elements), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Reconstruct(benchmark::State& state) {
    Synthetic s = make_scene(int(state.range(0)), 300, 42);
    SceneMeshes m;
    for (auto _ : state) {
        reconstruct_scene(s.scene, s.analyses, {}, &m);
        benchmark::DoNotOptimize(m.draws.data());
    }
    report(state, m);
}
BENCHMARK(BM_Reconstruct)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

void BM_ReconstructBoxes(benchmark::State& state) {
    Synthetic s = make_scene(int(state.range(0)), 300, 42);
    ReconstructOptions o;
    o.graph = GraphMode::boxes;
    SceneMeshes m;
    for (auto _ : state) {
        reconstruct_scene(s.scene, s.analyses, o, &m);
        benchmark::DoNotOptimize(m.draws.data());
    }
    report(state, m);
}
BENCHMARK(BM_ReconstructBoxes)->Arg(100000)->Unit(benchmark::kMillisecond);

void BM_ElementGraph(benchmark::State& state) {
    Synthetic s = make_scene(int(state.range(0)), 300, 42);
    for (auto _ : state) {
        ElementGraph g = build_element_graph(s.scene, s.analyses, GraphMode::polygons);
        benchmark::DoNotOptimize(g.targets.data());
        state.counters["edges"] = double(g.edge_count());
    }
}
BENCHMARK(BM_ElementGraph)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

// The sorts on one graph: batch (ours), paper (quadratic), painter's order.
void BM_Sort(benchmark::State& state) {
    Synthetic s = make_scene(int(state.range(0)), 300, 42);
    ElementGraph g = build_element_graph(s.scene, s.analyses, GraphMode::polygons);
    const SortMethod method = SortMethod(state.range(1));
    std::vector<std::uint32_t> order;
    for (auto _ : state) {
        order = sort_elements(s.scene, g, method);
        benchmark::DoNotOptimize(order.data());
    }
    state.counters["draws"] = double(count_batches(s.scene, order));
}
BENCHMARK(BM_Sort)
    ->Args({1000, int(SortMethod::none)})
    ->Args({1000, int(SortMethod::paper)})
    ->Args({1000, int(SortMethod::batch)})
    ->Args({10000, int(SortMethod::none)})
    ->Args({10000, int(SortMethod::paper)})
    ->Args({10000, int(SortMethod::batch)})
    ->Args({100000, int(SortMethod::none)})
    ->Args({100000, int(SortMethod::batch)})
    ->Unit(benchmark::kMillisecond);

// Dynamic elements: 1000 moving sprites over a 10k-element static scene.
void BM_DynamicFrame(benchmark::State& state) {
    Synthetic s = make_scene(10000, 300, 42);
    Synthetic moving = make_scene(1000, 300, 7);
    ReconstructOptions o;
    o.reserved_dynamic_levels = 4096;
    SceneMeshes base, frame;
    reconstruct_scene(s.scene, s.analyses, o, &base);
    // Same image list as the static scene (seeded the same way above).
    for (auto _ : state) {
        add_dynamic_elements(base, s.scene, moving.scene.elements, moving.analyses, &frame);
        benchmark::DoNotOptimize(frame.draws.data());
    }
    state.counters["draws"] = double(frame.stats.draw_calls);
}
BENCHMARK(BM_DynamicFrame)->Unit(benchmark::kMillisecond);

} // namespace

// The overdraw analyzer (depthcull/overdraw.h), which the cost model's
// chooser runs on every contestant frame: the meshes of ~750 elements in
// view of a 1024x768 camera. blocks: count 4x4 blocks too; depth: the
// reconstructed meshes (depth tested: work per fragment) or overpaint's
// (no depth test: work per row of each triangle).
void BM_AnalyzeOverdraw(benchmark::State& state) {
    Synthetic s = make_scene(3000, 300, 42);
    SceneMeshes m;
    if (state.range(1) != 0)
        reconstruct_scene(s.scene, s.analyses, {}, &m);
    else
        m = overpaint_meshes(s.scene);
    OverdrawStats stats;
    for (auto _ : state) {
        stats = analyze_overdraw(m, nullptr, state.range(0) != 0);
        benchmark::DoNotOptimize(stats.shaded);
    }
    state.counters["fragments"] = double(stats.rasterized);
    state.counters["fragments/s"] = benchmark::Counter(double(stats.rasterized), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_AnalyzeOverdraw)->ArgNames({"blocks", "depth"})->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond);

// --target's chooser (choose_for_target) on a ground of opaque 32x32 tiles
// under a second layer of the same tiles: side^2 x 2 elements, the whole
// grid in view. Each top tile hides the one below, so the chooser drops
// half the scene and its fallback reverts each tile's opaque polygon in
// turn. Time per element should stay about flat as the grid grows (the
// fallback once scanned the scene per tile it reverted: quadratic), and
// the depth buffer of each contestant frame stays within 16 MiB bands
// (the largest grid is 12800^2 px).
void BM_ChooseTileGrid(benchmark::State& state) {
    const int side = int(state.range(0)), tile = 32;
    Scene scene;
    scene.images.push_back({"tile", "tile.png", tile, tile});
    ImageAnalysis a;
    a.rect = {0, 0, tile, tile};
    a.boundary = {{{0, 0}, {double(tile), 0}, {double(tile), double(tile)}, {0, double(tile)}}};
    a.opaque = a.boundary;
    a.stats.nontransparent_texels = a.stats.opaque_texels = a.stats.opaque_covered_texels = std::int64_t(tile) * tile;
    for (int layer = 0; layer < 2; ++layer)
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x) {
                Element e;
                e.image = 0;
                e.rect = a.rect;
                e.transform = {1, 0, 0, 1, double(x * tile), double(y * tile)};
                scene.elements.push_back(e);
            }
    scene.viewport = {0, 0, side * tile, side * tile};
    std::vector<TargetCandidates> candidates(1);
    for (int budget : target_budgets(kMinBoundaryVertices)) {
        candidates[0].analyses.push_back(&a);
        candidates[0].max_vertices.push_back(budget);
    }
    const std::vector<int> element_key(scene.elements.size(), 0);
    CostProfile profile;
    builtin_profile("llvmpipe", &profile);
    TargetChoice choice;
    for (auto _ : state) {
        choice = choose_for_target(scene, candidates, element_key, profile, {});
        benchmark::DoNotOptimize(choice.predicted_ms);
    }
    state.counters["elements"] = double(scene.elements.size());
    state.counters["dropped"] = double(choice.elements_dropped);
    state.counters["per_element"] = benchmark::Counter(double(scene.elements.size()), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ChooseTileGrid)->Arg(50)->Arg(100)->Arg(200)->Arg(400)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

BENCHMARK_MAIN();
