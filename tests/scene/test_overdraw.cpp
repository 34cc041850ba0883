// The overdraw analyzers (depthcull/overdraw.h): exact counts on tiny
// hand-built frames, no GL.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <string>

#include "depthcull/overdraw.h"
#include "render/render_scenes.h"

namespace depthcull {
namespace {

SceneMeshes one_draw(Viewport vp, std::vector<Vec2> points, std::vector<std::uint32_t> indices, float z = 0,
                     Pass pass = Pass::blend, bool depth_test = false) {
    SceneMeshes m;
    m.viewport = vp;
    m.depth_test = depth_test;
    Draw d;
    d.pass = pass;
    for (Vec2 p : points) d.vertices.insert(d.vertices.end(), {float(p.x), float(p.y), z, 0, 0, 1, 1, 1, 1});
    d.indices = std::move(indices);
    m.draws.push_back(std::move(d));
    return m;
}

TEST(AnalyzeOverdraw, SquareSplitOnItsDiagonalShadesEachPixelOnce) {
    // The diagonal passes through every pixel centre on it: the fill rule
    // must give each of those to exactly one triangle.
    OverdrawMap map;
    auto m = one_draw({0, 0, 8, 8}, {{0, 0}, {8, 0}, {8, 8}, {0, 8}}, {0, 1, 2, 0, 2, 3});
    EXPECT_EQ(analyze_overdraw(m, &map).shaded, 64);
    for (auto c : map.counts) EXPECT_EQ(c, 1u);
    // The other diagonal, and the opposite winding.
    m = one_draw({0, 0, 8, 8}, {{0, 0}, {8, 0}, {8, 8}, {0, 8}}, {0, 3, 1, 1, 3, 2});
    EXPECT_EQ(analyze_overdraw(m).shaded, 64);
}

TEST(AnalyzeOverdraw, BlocksCountWhatEachTriangleTouches) {
    // A 64x64 quad on the 4x4 grid split on its diagonal: each half touches
    // the 136 blocks on its side of the diagonal, those on it included.
    auto m = one_draw({0, 0, 128, 128}, {{0, 0}, {64, 0}, {64, 64}, {0, 64}}, {0, 1, 2, 0, 2, 3});
    OverdrawStats s = analyze_overdraw(m, nullptr, true);
    EXPECT_EQ(s.blocks_blend, 272);
    EXPECT_EQ(s.blocks_opaque, 0);
    // One pixel off the grid: 17 block columns; shared blocks along the
    // vertical sides as well as the diagonal.
    m = one_draw({0, 0, 128, 128}, {{1, 0}, {65, 0}, {65, 64}, {1, 64}}, {0, 1, 2, 0, 2, 3}, 0, Pass::opaque);
    s = analyze_overdraw(m, nullptr, true);
    EXPECT_GT(s.blocks_opaque, 272);
    EXPECT_EQ(s.blocks_blend, 0);

    // Random triangles (thin slivers included): each one's blocks equal the
    // blocks its own coverage map touches.
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> coord(-8, 72);
    std::int64_t expected = 0;
    SceneMeshes all = one_draw({0, 0, 64, 48}, {}, {});
    for (int t = 0; t < 300; ++t) {
        std::vector<Vec2> p = {{coord(rng), coord(rng)}, {coord(rng), coord(rng)}, {coord(rng), coord(rng)}};
        if (t % 3 == 0) p[2] = {p[0].x + 0.3 * (p[1].x - p[0].x) + 0.7, p[0].y + 0.3 * (p[1].y - p[0].y) - 0.4};
        OverdrawMap map;
        analyze_overdraw(one_draw({0, 0, 64, 48}, p, {0, 1, 2}), &map);
        std::set<std::pair<int, int>> blocks;
        for (int y = 0; y < map.height; ++y)
            for (int x = 0; x < map.width; ++x)
                if (map.counts[std::size_t(y * map.width + x)]) blocks.insert({x / 4, y / 4});
        expected += std::int64_t(blocks.size());
        const auto base = std::uint32_t(all.draws[0].vertex_count());
        for (Vec2 v : p) all.draws[0].vertices.insert(all.draws[0].vertices.end(), {float(v.x), float(v.y), 0, 0, 0, 1, 1, 1, 1});
        all.draws[0].indices.insert(all.draws[0].indices.end(), {base, base + 1, base + 2});
    }
    EXPECT_EQ(analyze_overdraw(all, nullptr, true).blocks_blend, expected);
    EXPECT_EQ(analyze_overdraw(all).blocks_blend, 0); // not asked for
}

TEST(AnalyzeOverdraw, FanThroughPixelCentresTilesOnce) {
    // Eight triangles around (4.5, 4.5), a pixel centre; spokes run through
    // pixel centres horizontally, vertically and diagonally.
    std::vector<Vec2> p = {{4.5, 4.5}, {0, 0}, {4.5, 0}, {9, 0}, {9, 4.5}, {9, 9}, {4.5, 9}, {0, 9}, {0, 4.5}};
    std::vector<std::uint32_t> idx;
    for (std::uint32_t i = 1; i <= 8; ++i) idx.insert(idx.end(), {0, i, i % 8 + 1});
    OverdrawMap map;
    EXPECT_EQ(analyze_overdraw(one_draw({0, 0, 9, 9}, p, idx), &map).shaded, 81);
    for (auto c : map.counts) EXPECT_EQ(c, 1u);
}

TEST(AnalyzeOverdraw, VerticesFarOutsideTheViewportKeepTheirEdges) {
    // A sprite scaled up or placed far out can put a vertex of a triangle
    // still in view millions of pixels away, where edge values no longer
    // fit 64 bits. The same edge lines, through vertices near and far,
    // cover the same centres.
    for (double far : {1e6, 1e7, 5e7, 1.3e8, 1e12}) {
        const double near = 100;
        // Edges through the origin at slopes 1 and -1: y >= |x|, ties by the fill rule.
        const auto wedge = [](double d) { return one_draw({-4, 0, 8, 8}, {{0, 0}, {d, d}, {-d, d}}, {0, 1, 2}); };
        EXPECT_EQ(analyze_overdraw(wedge(far)).shaded, analyze_overdraw(wedge(near)).shaded) << far;
        // Rows of centres y = 0.5 .. 7.5 hold 2, 4, 6, then 8 centres with
        // |x| <= y: 52, of which the 8 on the edges go 4 to each side.
        EXPECT_EQ(analyze_overdraw(wedge(far)).shaded, 48) << far;
        // A triangle around the whole viewport.
        EXPECT_EQ(analyze_overdraw(one_draw({0, 0, 8, 8}, {{-far, -far}, {far, -far}, {0.5, far}}, {0, 1, 2})).shaded, 64) << far;
    }
}

// The rasterizer finds each row's run of covered centres by division; this
// tests every centre on its own, as GL's rule states it (vertices snapped
// to 1/256 px, edge values in 128 bits, centres exactly on an edge kept by
// top and left edges), and counts per pixel.
std::vector<std::uint32_t> covered_by_brute_force(const SceneMeshes& m) {
    __extension__ typedef __int128 Wide;
    const int w = m.viewport.width, h = m.viewport.height;
    std::vector<std::uint32_t> counts(std::size_t(w) * std::size_t(h), 0);
    for (const Draw& d : m.draws)
        for (std::size_t t = 0; t + 3 <= d.indices.size(); t += 3) {
            Wide x[3], y[3];
            for (int k = 0; k < 3; ++k) {
                const float* v = &d.vertices[std::size_t(d.indices[t + std::size_t(k)]) * kVertexFloats];
                x[k] = std::llround((double(v[0]) - m.viewport.x) * 256), y[k] = std::llround((double(v[1]) - m.viewport.y) * 256);
            }
            const auto edge = [&](int p, int q, Wide px, Wide py) { return -(y[q] - y[p]) * (px - x[p]) + (x[q] - x[p]) * (py - y[p]); };
            Wide area = edge(0, 1, x[2], y[2]);
            if (area == 0) continue;
            if (area < 0) std::swap(x[1], x[2]), std::swap(y[1], y[2]);
            const int from[3] = {1, 2, 0}, to[3] = {2, 0, 1};
            for (int py = 0; py < h; ++py)
                for (int px = 0; px < w; ++px) {
                    bool inside = true;
                    for (int k = 0; k < 3 && inside; ++k) {
                        const Wide dx = x[to[k]] - x[from[k]], dy = y[to[k]] - y[from[k]];
                        const bool ties_inside = dy < 0 || (dy == 0 && dx > 0);
                        inside = edge(from[k], to[k], Wide(px) * 256 + 128, Wide(py) * 256 + 128) >= (ties_inside ? 0 : 1);
                    }
                    counts[std::size_t(py) * std::size_t(w) + std::size_t(px)] += inside;
                }
        }
    return counts;
}

TEST(AnalyzeOverdraw, RowRunsAreWhatTestingEveryCentreGives) {
    std::mt19937 rng(11);
    // Vertices on pixel centres and corners (edges through centres, ties
    // everywhere), on the subpixel grid, and some far out (128-bit edges).
    for (int grid : {2, 256, -1}) {
        SceneMeshes m;
        m.viewport = {-3, 2, 37, 29};
        Draw d;
        std::uniform_int_distribution<int> x(-8 * 16, 44 * 16), y(-8 * 16, 40 * 16), far(0, 9);
        for (int i = 0; i < 600; ++i) {
            double vx = double(x(rng)) / 16, vy = double(y(rng)) / 16;
            if (grid > 0) vx = std::round(vx * grid) / grid, vy = std::round(vy * grid) / grid;
            if (grid < 0 && far(rng) == 0) vx *= 3e6, vy *= -2e6;
            d.vertices.insert(d.vertices.end(), {float(vx), float(vy), 0, 0, 0, 1, 1, 1, 1});
        }
        for (std::uint32_t i = 0; i + 2 < 600; i += 3) d.indices.insert(d.indices.end(), {i, i + 1, i + 2});
        m.draws.push_back(d);
        const std::vector<std::uint32_t> expected = covered_by_brute_force(m);
        std::int64_t total = 0;
        for (std::uint32_t c : expected) total += c;
        OverdrawMap map;
        EXPECT_EQ(analyze_overdraw(m, &map).shaded, total) << "grid " << grid; // per pixel
        EXPECT_EQ(map.counts, expected) << "grid " << grid;
        EXPECT_EQ(analyze_overdraw(m).shaded, total) << "grid " << grid; // runs only
        EXPECT_EQ(analyze_overdraw(m, nullptr, true).shaded, total) << "grid " << grid;
        EXPECT_GT(total, 1000);
    }
}

TEST(AnalyzeOverdraw, DepthTestedRunsCountWhatTestingEveryFragmentGives) {
    // Counting runs (no map) and counting fragments (a map) share the
    // depth test's arithmetic: random overlapping triangles at slanted
    // depths, in both passes, give the same counts either way.
    std::mt19937 rng(5);
    SceneMeshes m;
    m.viewport = {0, 0, 32, 24};
    m.depth_test = true;
    std::uniform_real_distribution<double> x(-4, 36), y(-4, 28), z(0, 1);
    for (int k = 0; k < 6; ++k) {
        Draw d;
        d.pass = k < 3 ? Pass::opaque : Pass::blend;
        for (int i = 0; i < 90; ++i) d.vertices.insert(d.vertices.end(), {float(x(rng)), float(y(rng)), float(z(rng)), 0, 0, 1, 1, 1, 1});
        for (std::uint32_t i = 0; i + 2 < 90; i += 3) d.indices.insert(d.indices.end(), {i, i + 1, i + 2});
        m.draws.push_back(std::move(d));
    }
    OverdrawMap map;
    const OverdrawStats by_fragment = analyze_overdraw(m, &map), by_run = analyze_overdraw(m);
    EXPECT_EQ(by_run.rasterized, by_fragment.rasterized);
    EXPECT_EQ(by_run.shaded, by_fragment.shaded);
    EXPECT_EQ(by_run.shaded_opaque, by_fragment.shaded_opaque);
    EXPECT_LT(by_run.shaded, by_run.rasterized); // the test rejected some
    EXPECT_GT(by_run.shaded_opaque, 0);
}

TEST(AnalyzeOverdraw, AFrameInTheCornerOfAHugeViewportCountsAsInItsOwn) {
    // The depth buffer spans only what the triangles reach (a whole map's
    // viewport would cost 1 GiB): the same depth-tested frame, seen in the
    // far corner of a 16384^2 viewport (whole blocks from its origin, and
    // partly beyond its right and bottom sides), counts what it counts in
    // a viewport of its own.
    std::mt19937 rng(11);
    SceneMeshes own;
    own.viewport = {0, 0, 40, 32};
    own.depth_test = true;
    std::uniform_real_distribution<double> x(0, 46), y(0, 38), z(0, 1);
    for (int k = 0; k < 6; ++k) {
        Draw d;
        d.pass = k % 2 ? Pass::blend : Pass::opaque;
        for (int i = 0; i < 60; ++i) d.vertices.insert(d.vertices.end(), {float(x(rng)), float(y(rng)), float(z(rng)), 0, 0, 1, 1, 1, 1});
        for (std::uint32_t i = 0; i + 2 < 60; i += 3) d.indices.insert(d.indices.end(), {i, i + 1, i + 2});
        own.draws.push_back(std::move(d));
    }
    const OverdrawStats expected = analyze_overdraw(own, nullptr, true);
    EXPECT_LT(expected.shaded, expected.rasterized);
    SceneMeshes corner = own;
    corner.viewport = {-16344, -16352, 16384, 16384}; // its bottom-right 40x32 pixels are `own`'s
    const OverdrawStats got = analyze_overdraw(corner, nullptr, true);
    EXPECT_EQ(got.rasterized, expected.rasterized);
    EXPECT_EQ(got.shaded, expected.shaded);
    EXPECT_EQ(got.shaded_opaque, expected.shaded_opaque);
    EXPECT_EQ(got.blocks_opaque, expected.blocks_opaque);
    EXPECT_EQ(got.blocks_blend, expected.blocks_blend);
    EXPECT_EQ(got.pixels, 16384LL * 16384);
}

TEST(AnalyzeOverdraw, AFrameTooLargeForOneDepthBufferCountsAsItsStrips) {
    // A depth-tested frame of more than 2^22 pixels is rasterized in bands
    // of rows with one band's depth buffer at a time. Each pixel's count
    // depends only on the fragments at that pixel, in drawing order, so the
    // frame counts what its strips count, each seen through a viewport of
    // its own small enough to be rasterized whole. The strips (600 rows, a
    // multiple of 4 so their 4x4 blocks are the frame's) do not line up
    // with the bands (696 rows for 6000 columns).
    std::mt19937 rng(7);
    SceneMeshes whole;
    whole.viewport = {-20, 30, 6000, 1400};
    whole.depth_test = true;
    // Vertices on the 1/256 px grid the rasterizer snaps to: a tie between
    // two snapped positions rounds away from zero, so it could snap apart
    // when a strip's viewport moves the vertex past 0.
    std::uniform_real_distribution<double> x(-400, 6400), y(-200, 1600), z(0, 1), small(-40, 40);
    auto on_grid = [](double v) { return float(std::round(v * 256) / 256); };
    for (int k = 0; k < 6; ++k) {
        Draw d;
        d.pass = k < 3 ? Pass::opaque : Pass::blend;
        // Large triangles across several bands, and small ones on their seams.
        for (int i = 0; i < 60; ++i) d.vertices.insert(d.vertices.end(), {on_grid(x(rng)), on_grid(y(rng)), float(z(rng)), 0, 0, 1, 1, 1, 1});
        for (int i = 0; i < 60; ++i) {
            const double cx = x(rng), cy = 30 + 696 * double(1 + i % 2) + small(rng) / 8;
            for (int v = 0; v < 3; ++v)
                d.vertices.insert(d.vertices.end(), {on_grid(cx + small(rng)), on_grid(cy + small(rng)), float(z(rng)), 0, 0, 1, 1, 1, 1});
        }
        for (std::uint32_t i = 0; i + 2 < 240; i += 3) d.indices.insert(d.indices.end(), {i, i + 1, i + 2});
        d.indices.insert(d.indices.end(), {0, 1, 999}); // past the vertices: not drawn
        whole.draws.push_back(std::move(d));
    }
    OverdrawMap map;
    const OverdrawStats got = analyze_overdraw(whole, nullptr, true), got_map = analyze_overdraw(whole, &map, true);
    OverdrawStats sum;
    std::vector<std::uint32_t> counts;
    for (int row = 0; row < 1400; row += 600) {
        SceneMeshes strip = whole;
        strip.viewport = {whole.viewport.x, whole.viewport.y + row, 6000, std::min(600, 1400 - row)};
        OverdrawMap strip_map;
        const OverdrawStats s = analyze_overdraw(strip, &strip_map, true);
        sum.rasterized += s.rasterized, sum.shaded += s.shaded, sum.shaded_opaque += s.shaded_opaque;
        sum.blocks_opaque += s.blocks_opaque, sum.blocks_blend += s.blocks_blend;
        counts.insert(counts.end(), strip_map.counts.begin(), strip_map.counts.end());
    }
    for (const OverdrawStats& s : {got, got_map}) {
        EXPECT_EQ(s.rasterized, sum.rasterized);
        EXPECT_EQ(s.shaded, sum.shaded);
        EXPECT_EQ(s.shaded_opaque, sum.shaded_opaque);
        EXPECT_EQ(s.blocks_opaque, sum.blocks_opaque);
        EXPECT_EQ(s.blocks_blend, sum.blocks_blend);
    }
    EXPECT_EQ(map.counts, counts);
    EXPECT_LT(got.shaded, got.rasterized); // the depth test rejected some
    EXPECT_GT(got.shaded_opaque, 0);
    EXPECT_GT(got.rasterized, 6000LL * 1400);
}

TEST(AnalyzeOverdraw, ViewportOffsetAndClipping) {
    // A 4x4 square at world (10, 20) seen through a viewport at (12, 21):
    // 2 columns x 3 rows remain.
    auto m = one_draw({12, 21, 5, 5}, {{10, 20}, {14, 20}, {14, 24}, {10, 24}}, {0, 1, 2, 0, 2, 3});
    OverdrawMap map;
    EXPECT_EQ(analyze_overdraw(m, &map).shaded, 6);
    EXPECT_EQ(map.counts[0], 1u);
    EXPECT_EQ(map.counts[2], 0u);
}

TEST(AnalyzeOverdraw, DepthTestCountsOnlyWhatPasses) {
    // Opaque pass: near square first, then a far one under it: the far one
    // only shades outside the near one. Blend draws test but do not write.
    SceneMeshes m;
    m.viewport = {0, 0, 4, 4};
    m.depth_test = true;
    auto quad = [](double x0, double y0, double x1, double y1, float z, Pass pass) {
        Draw d;
        d.pass = pass;
        for (Vec2 p : {Vec2{x0, y0}, Vec2{x1, y0}, Vec2{x1, y1}, Vec2{x0, y1}})
            d.vertices.insert(d.vertices.end(), {float(p.x), float(p.y), z, 0, 0, 1, 1, 1, 1});
        d.indices = {0, 1, 2, 0, 2, 3};
        return d;
    };
    m.draws.push_back(quad(0, 0, 2, 2, 0.75f, Pass::opaque)); // 4
    m.draws.push_back(quad(0, 0, 4, 4, 0.25f, Pass::opaque)); // 16 - 4
    m.draws.push_back(quad(0, 0, 4, 4, 0.5f, Pass::blend));   // passes where 0.25: 12
    m.draws.push_back(quad(0, 0, 4, 4, 0.5f, Pass::blend));   // no write: 12 again
    EXPECT_EQ(analyze_overdraw(m).shaded, 4 + 12 + 12 + 12);
}

TEST(IdealOverdraw, StopsAtTheFirstFullyOpaqueElement) {
    test::RenderScene rs;
    rs.scene.viewport = {0, 0, 4, 4};
    const int solid = rs.add_image(test::ascii_image({"##", "##"}), {0, 0, 2, 2});
    const int glass = rs.add_image(test::ascii_image({"++", "+."}), {});
    rs.add(solid, {2, 0, 0, 2, 0, 0});                                   // covers all 16
    rs.add(solid, {1, 0, 0, 1, 1, 1});                                   // 4 pixels, opaque
    rs.add(glass, {1, 0, 0, 1, 1, 1});                                   // 3 non-transparent
    rs.add(solid, {1, 0, 0, 1, 2, 2}, Blend::alpha, {1, 1, 1, 0.5f});    // 4, not covering
    OverdrawMap map;
    auto stats = ideal_overdraw(rs.scene, rs.views(), &map);
    // Pixel (1,1): glass + solid = 2 (background hidden). (2,2): half-solid,
    // glass(.)=transparent, solid -> 2. (2,1),(1,2): glass + solid = 2.
    // (3,3),(2,3),(3,2): half-solid + background = 2. Others: background 1.
    EXPECT_EQ(map.counts[1 * 4 + 1], 2u);
    EXPECT_EQ(map.counts[2 * 4 + 2], 2u);
    EXPECT_EQ(map.counts[3 * 4 + 3], 2u);
    EXPECT_EQ(map.counts[0], 1u);
    EXPECT_EQ(stats.shaded, 9 * 1 + 7 * 2);
    // Overpaint shades every rect pixel: 16 + 4 + 4 + 4.
    EXPECT_EQ(analyze_overdraw(overpaint_meshes(rs.scene)).shaded, 28);
}

TEST(IdealOverdraw, IsALowerBoundOfTheHandOptimizedScene) {
    auto rs = test::mixed_scene();
    auto ideal = ideal_overdraw(rs.scene, rs.views());
    auto over = analyze_overdraw(overpaint_meshes(rs.scene));
    auto opt = analyze_overdraw(test::hand_optimized(rs));
    EXPECT_LT(opt.shaded, over.shaded);
    EXPECT_LE(ideal.shaded, opt.shaded);
    EXPECT_EQ(over.pixels, 64 * 48);
}

TEST(IdealOverdraw, AFrameInTheCornerOfAHugeViewportCountsAsInItsOwn) {
    // What is hidden is kept only over the box the elements cover (a whole
    // map's viewport would cost 256 MB): the mixed scene seen in the far
    // corner of a 16384^2 viewport (whole blocks from its origin) counts
    // what it counts in its own 64x48 one.
    auto rs = test::mixed_scene();
    const Viewport vp = rs.scene.viewport;
    ASSERT_EQ(vp.width, 64);
    ASSERT_EQ(vp.height, 48);
    std::vector<std::uint8_t> shows_own, shows_corner;
    const OverdrawStats own = ideal_overdraw(rs.scene, rs.views(), nullptr, &shows_own);
    rs.scene.viewport = {vp.x + 64 - 16384, vp.y + 48 - 16384, 16384, 16384};
    const OverdrawStats corner = ideal_overdraw(rs.scene, rs.views(), nullptr, &shows_corner);
    EXPECT_EQ(corner.shaded, own.shaded);
    EXPECT_EQ(corner.blocks_opaque, own.blocks_opaque);
    EXPECT_EQ(corner.blocks_blend, own.blocks_blend);
    EXPECT_EQ(shows_corner, shows_own);
    EXPECT_GT(own.blocks_opaque, 0);
}

TEST(AnalyzeOverdraw, RasterizedCountsWhatTheDepthTestRejects) {
    // A near opaque quad, then a far one under it: 4 + 16 covered, 4 + 12 shaded.
    SceneMeshes m;
    m.viewport = {0, 0, 4, 4};
    m.depth_test = true;
    auto quad = [](double x1, double y1, float z) {
        Draw d;
        d.pass = Pass::opaque;
        for (Vec2 p : {Vec2{0, 0}, Vec2{x1, 0}, Vec2{x1, y1}, Vec2{0, y1}})
            d.vertices.insert(d.vertices.end(), {float(p.x), float(p.y), z, 0, 0, 1, 1, 1, 1});
        d.indices = {0, 1, 2, 0, 2, 3};
        return d;
    };
    m.draws.push_back(quad(2, 2, 0.75f));
    m.draws.push_back(quad(4, 4, 0.25f));
    const OverdrawStats s = analyze_overdraw(m);
    EXPECT_EQ(s.rasterized, 20);
    EXPECT_EQ(s.shaded, 16);
    m.depth_test = false;
    EXPECT_EQ(analyze_overdraw(m).shaded, 20);
}

TEST(ExcessOverdraw, SortsFragmentsByTheTexelTheySample) {
    // The frame of StopsAtTheFirstFullyOpaqueElement, drawn as overpaint:
    // 28 fragments, of which the ideal frame's 23, the glass's transparent
    // texel and the 4 background pixels under the opaque square.
    test::RenderScene rs;
    rs.scene.viewport = {0, 0, 4, 4};
    const int solid = rs.add_image(test::ascii_image({"##", "##"}), {0, 0, 2, 2});
    const int glass = rs.add_image(test::ascii_image({"++", "+."}), {});
    rs.add(solid, {2, 0, 0, 2, 0, 0});
    rs.add(solid, {1, 0, 0, 1, 1, 1});
    rs.add(glass, {1, 0, 0, 1, 1, 1});
    rs.add(solid, {1, 0, 0, 1, 2, 2}, Blend::alpha, {1, 1, 1, 0.5f});
    const ExcessStats e = excess_overdraw(overpaint_meshes(rs.scene), rs.views());
    EXPECT_EQ(e.needed, ideal_overdraw(rs.scene, rs.views()).shaded);
    EXPECT_EQ(e.needed, 23);
    EXPECT_EQ(e.transparent, 1);
    EXPECT_EQ(e.hidden, 4);
}

TEST(ExcessOverdraw, OverlappingOpaquePiecesWithoutDepthShadeTwice) {
    // One element's two opaque pieces overlapping in the middle two columns,
    // drawn without a depth buffer: the second fragment there is not needed.
    SceneMeshes m = one_draw({0, 0, 4, 4}, {{0, 0}, {3, 0}, {3, 4}, {0, 4}, {1, 0}, {4, 0}, {4, 4}, {1, 4}},
                             {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7}, 0.5f, Pass::opaque);
    m.depth_denominator = 4;
    const Image solid = test::ascii_image({"####", "####", "####", "####"});
    const ExcessStats e = excess_overdraw(m, {solid.view()});
    EXPECT_EQ(analyze_overdraw(m).shaded, 24);
    EXPECT_EQ(e.needed, 16);
    EXPECT_EQ(e.hidden, 8);
    EXPECT_EQ(e.transparent, 0);
    // With the depth test the second is rejected, not shaded.
    m.depth_test = true;
    const ExcessStats tested = excess_overdraw(m, {solid.view()});
    EXPECT_EQ(tested.needed, 16);
    EXPECT_EQ(tested.hidden, 0);
}

// A w x h image of one character ('#' opaque, '+' translucent, '.'
// transparent), or two side by side.
Image filled(int w, int h, char left, char right = 0) {
    std::vector<std::string> rows(std::size_t(h), std::string(std::size_t(w), left));
    if (right)
        for (std::string& r : rows) std::fill(r.begin() + w / 2, r.end(), right);
    return test::ascii_image(rows);
}

TEST(IdealOverdraw, BlocksAreWhatTheLimitsTwoTrianglesPerElementShade) {
    // One opaque 64x64 element on the 4x4 grid: its two triangles shade the
    // blocks of AnalyzeOverdraw.BlocksCountWhatEachTriangleTouches, 272,
    // every one opaque; overpaint draws the same quad.
    test::RenderScene rs;
    rs.scene.viewport = {0, 0, 128, 128};
    const int solid = rs.add_image(filled(64, 64, '#'), {0, 0, 64, 64});
    rs.add(solid, {1, 0, 0, 1, 0, 0});
    OverdrawStats ideal = ideal_overdraw(rs.scene, rs.views());
    EXPECT_EQ(ideal.blocks_opaque, 272);
    EXPECT_EQ(ideal.blocks_blend, 0);
    EXPECT_EQ(analyze_overdraw(overpaint_meshes(rs.scene), nullptr, true).blocks_blend, 272);

    // Translucent by its colour: the same blocks, blended.
    rs.scene.elements[0].color = {1, 1, 1, 0.5f};
    ideal = ideal_overdraw(rs.scene, rs.views());
    EXPECT_EQ(ideal.blocks_opaque, 0);
    EXPECT_EQ(ideal.blocks_blend, 272);

    // Its right half transparent: the left half's 8 x 16 blocks, and the 8
    // on the diagonal (from texel (0, 0) to (64, 64)) twice.
    test::RenderScene half;
    half.scene.viewport = {0, 0, 128, 128};
    half.add(half.add_image(filled(64, 64, '#', '.'), {}), {1, 0, 0, 1, 0, 0});
    ideal = ideal_overdraw(half.scene, half.views());
    EXPECT_EQ(ideal.blocks_opaque, 136);
    EXPECT_EQ(ideal.blocks_blend, 0);
    // Translucent texels there instead: blended.
    half.images[0] = filled(64, 64, '+', '.');
    ideal = ideal_overdraw(half.scene, half.views());
    EXPECT_EQ(ideal.blocks_opaque, 0);
    EXPECT_EQ(ideal.blocks_blend, 136);

    // Off the grid, turned and scaled, side by side and nothing hidden:
    // overpaint draws exactly the ideal frame, blocks included.
    test::RenderScene apart;
    apart.scene.viewport = {0, 0, 160, 96};
    const int a = apart.add_image(filled(24, 40, '#'), {0, 0, 24, 40});
    const int b = apart.add_image(filled(30, 10, '+'), {});
    apart.add(a, {1, 0, 0, 1, 2, 1});
    apart.add(a, {0, 1, -1, 0, 90.25, 3}); // a quarter turn, no centre on its edges
    apart.add(b, {2, 0, 0, 1.5, 97, 50});
    ideal = ideal_overdraw(apart.scene, apart.views());
    const OverdrawStats over = analyze_overdraw(overpaint_meshes(apart.scene), nullptr, true);
    EXPECT_EQ(ideal.shaded, over.shaded);
    EXPECT_EQ(ideal.blocks_opaque + ideal.blocks_blend, over.blocks_blend);
    EXPECT_GT(ideal.blocks_blend, 0);
    EXPECT_GT(ideal.blocks_opaque, 0);
}

TEST(ExcessOverdraw, BlocksHoldingNoNeededFragmentAreWaste) {
    // A 16x8 opaque background split on its diagonal (slope 1/2), an 8x8
    // opaque square over its left half, drawn as overpaint. The background
    // triangles' 6 blocks under the square (two on each block of the
    // slope's first column, one on the others) hold hidden fragments only;
    // its 6 on the right and the square's 6 (its diagonal's two blocks
    // twice) hold needed ones, as many as the ideal frame's.
    test::RenderScene rs;
    rs.scene.viewport = {0, 0, 16, 8};
    const int ground = rs.add_image(filled(16, 8, '#'), {0, 0, 16, 8});
    const int square = rs.add_image(filled(8, 8, '#'), {0, 0, 8, 8});
    rs.add(ground, {1, 0, 0, 1, 0, 0});
    rs.add(square, {1, 0, 0, 1, 0, 0});
    const SceneMeshes over = overpaint_meshes(rs.scene);
    const ExcessStats e = excess_overdraw(over, rs.views());
    EXPECT_EQ(e.blocks_needed, 12);
    EXPECT_EQ(e.blocks_waste, 6);
    EXPECT_EQ(e.blocks_needed + e.blocks_waste, analyze_overdraw(over, nullptr, true).blocks_blend);
    const OverdrawStats ideal = ideal_overdraw(rs.scene, rs.views());
    EXPECT_EQ(ideal.blocks_opaque, 12);
    EXPECT_EQ(ideal.blocks_blend, 0);
}

TEST(SummaryCounts, MatchTheMeshesTheyStandFor) {
    auto rs = test::mixed_scene();
    const SceneMeshes over = overpaint_meshes(rs.scene);
    const SceneStats counted = overpaint_stats(rs.scene);
    EXPECT_EQ(counted.draw_calls, over.stats.draw_calls);
    EXPECT_EQ(counted.triangles, over.stats.triangles);
    for (SortMethod sort : {SortMethod::batch, SortMethod::paper, SortMethod::none}) {
        for (bool cull : {false, true}) {
            ReconstructOptions options;
            options.sort = sort;
            options.cull_to_viewport = cull;
            SceneMeshes rects;
            SceneStats stats;
            ASSERT_EQ(rectangle_meshes(rs.scene, options, &rects), ReconstructStatus::ok);
            ASSERT_EQ(rectangle_stats(rs.scene, options, &stats), ReconstructStatus::ok);
            EXPECT_EQ(stats.draw_calls, rects.stats.draw_calls);
            EXPECT_EQ(stats.triangles, rects.stats.triangles);
            EXPECT_EQ(stats.graph_edges, rects.stats.graph_edges);
            // Meshes only rasterizes what overpaint does (optimize --stats relies on it).
            if (!cull) {
                EXPECT_EQ(analyze_overdraw(rects).shaded, analyze_overdraw(over).shaded);
            }
        }
    }
}

} // namespace
} // namespace depthcull
