// Boundary polygons (paper 2.1) over the pingus-data sprites: analysis time
// per image and the excess-area ratio (boundary area / non-transparent
// texels; 1.0 is a perfect fit) of
//   - ours: generate_boundary_polygons (nearest, linear, --no-split),
//   - the plain bounding box (what the paper starts from),
//   - the convex hull of the texel squares reduced to the same vertex budget
//     by removing the vertex whose removal (extending its neighbours' edges)
//     adds the least area, keeping every texel inside and the rect bounds.
// Run: build-*/bench/bench_boundary (needs scripts/fetch-corpus).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "boundary/boundary_internal.h"
#include "depthcull/analyze.h"
#include "depthcull/io.h"
#include "testing/corpus.h"

using namespace depthcull;
using namespace depthcull::boundary;

namespace {

struct Sprite {
    Image image;
    std::int64_t texels = 0;
};

const std::vector<Sprite>& corpus() {
    static const std::vector<Sprite> sprites = [] {
        std::vector<Sprite> out;
        if (!test::corpus_missing("pingus-data").empty()) return out;
        for (const std::string& path : test::corpus_files("pingus-data", ".png")) {
            Sprite s;
            try {
                s.image = io::read_png(path);
            } catch (const depthcull::Error&) {
                continue;
            }
            for (std::size_t i = 3; i < s.image.rgba.size(); i += 4) s.texels += s.image.rgba[i] != 0;
            if (s.texels) out.push_back(std::move(s));
        }
        return out;
    }();
    return sprites;
}

// ---- Benchmarks

struct Totals {
    double area = 0, texels = 0, vertices = 0, polygons = 0, over_budget = 0, uncontained = 0;
    double seconds = 0; // wall time of the timed loop's last pass
};

void report(benchmark::State& state, const Totals& t, std::size_t images) {
    state.counters["images"] = double(images);
    state.counters["excess_ratio"] = t.texels ? t.area / t.texels : 0;
    state.counters["vertices_per_image"] = images ? t.vertices / double(images) : 0;
    state.counters["polygons_per_image"] = images ? t.polygons / double(images) : 0;
    state.counters["over_budget"] = t.over_budget;
    state.counters["uncontained"] = t.uncontained;
    state.counters["ms_per_image"] = images ? 1000.0 * t.seconds / double(images) : 0;
}

void BM_Ours(benchmark::State& state, Filter filter, bool split) {
    const auto& sprites = corpus();
    if (sprites.empty()) return state.SkipWithError("pingus-data corpus missing: run scripts/fetch-corpus");
    BoundaryOptions o;
    o.split_parts = split;
    Totals t;
    for (auto _ : state) {
        t = {};
        const auto start = std::chrono::steady_clock::now();
        for (const Sprite& s : sprites) {
            auto polys = generate_boundary_polygons(s.image.view(), s.image.view().bounds(), o, filter);
            t.area += total_area(polys);
            t.texels += double(s.texels);
            t.polygons += double(polys.size());
            for (const auto& p : polys) t.vertices += double(p.size()), t.over_budget += p.size() > 10u;
        }
        t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    for (const Sprite& s : sprites) // the guarantee, checked exactly; outside the timed loop
        t.uncontained += double(count_uncontained_texels(
            s.image.view(), s.image.view().bounds(),
            generate_boundary_polygons(s.image.view(), s.image.view().bounds(), o, filter), filter));
    report(state, t, sprites.size());
}

void BM_BoundingBox(benchmark::State& state) {
    const auto& sprites = corpus();
    if (sprites.empty()) return state.SkipWithError("pingus-data corpus missing: run scripts/fetch-corpus");
    Totals t;
    for (auto _ : state) {
        t = {};
        const auto start = std::chrono::steady_clock::now();
        for (const Sprite& s : sprites) {
            CellGrid g = make_cell_grid(s.image.view(), s.image.view().bounds(), Filter::nearest);
            Bounds b = g.box();
            t.area += double((b.x1 - b.x0) * (b.y1 - b.y0));
            t.texels += double(s.texels);
            t.vertices += 4;
            t.polygons += 1;
        }
        t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    report(state, t, sprites.size());
}

void BM_ReducedConvexHull(benchmark::State& state) {
    const auto& sprites = corpus();
    if (sprites.empty()) return state.SkipWithError("pingus-data corpus missing: run scripts/fetch-corpus");
    Totals t;
    for (auto _ : state) {
        t = {};
        const auto start = std::chrono::steady_clock::now();
        for (const Sprite& s : sprites) {
            CellGrid g = make_cell_grid(s.image.view(), s.image.view().bounds(), Filter::nearest);
            IPolygon p = reduced_convex_hull(g, {0, 0, g.width(), g.height()}, 10);
            if (p.empty()) p = convex_hull(g); // the budget cannot be met inside the rect
            t.area += double(twice_area(p)) / 2;
            t.texels += double(s.texels);
            t.vertices += double(p.size());
            t.over_budget += p.size() > 10u; // the rect bounds can stop the reduction
            t.polygons += 1;
            if (!boundary::is_simple(p) || !contains_all_cells(g, p)) t.uncontained += 1;
        }
        t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    report(state, t, sprites.size());
}

} // namespace

BENCHMARK_CAPTURE(BM_Ours, nearest, Filter::nearest, true)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_Ours, nearest_no_split, Filter::nearest, false)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_Ours, linear, Filter::linear, true)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_BoundingBox)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_ReducedConvexHull)->Unit(benchmark::kMillisecond)->Iterations(1);

BENCHMARK_MAIN();
