// "The look never changes": a small software rasterizer draws random
// scenes the plain way (overpaint) and from the reconstructed meshes, with
// the renderer contract of docs/mesh-format.md (opaque pass: GL_GREATER,
// depth write, no blending; blend pass: GL_GREATER, no depth write), and
// the two frames must be identical, pixel for pixel. Transforms are integer
// translations with quarter turns and mirrors, so every pixel centre maps
// to a texel centre and nearest sampling is exact in both paths; the
// images and their analyses are real (random shapes through analyze_image).
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "depthcull/overdraw.h"
#include "depthcull/scene.h"
#include "scene/internal.h"
#include "testing/random_shapes.h"

namespace depthcull::test {
namespace {

struct Frame {
    int w = 0, h = 0;
    std::vector<double> rgb, depth;
};

struct Texel {
    double r, g, b, a;
};

Texel sample(const Image& img, double u, double v) {
    int x = std::clamp(int(std::floor(u * img.width)), 0, img.width - 1);
    int y = std::clamp(int(std::floor(v * img.height)), 0, img.height - 1);
    const std::uint8_t* t = img.view().texel(x, y);
    return {t[0] / 255.0, t[1] / 255.0, t[2] / 255.0, t[3] / 255.0};
}

// Top-left style ownership so a pixel centre on an edge shared by two
// triangles of one polygon is drawn exactly once.
bool owns(Vec2 a, Vec2 b) { return (b.y - a.y) > 0 || ((b.y - a.y) == 0 && (b.x - a.x) < 0); }
bool inside(Vec2 a, Vec2 b, Vec2 p) {
    double e = orient(a, b, p);
    return e > 0 || (e == 0 && owns(a, b));
}

void draw(Frame& f, const Draw& d, const std::vector<Image>& images, bool depth_test) {
    const Image& img = images[std::size_t(d.image)];
    auto vert = [&](std::uint32_t i) { return &d.vertices[std::size_t(i) * kVertexFloats]; };
    for (std::size_t t = 0; t < d.indices.size(); t += 3) {
        const float* v[3] = {vert(d.indices[t]), vert(d.indices[t + 1]), vert(d.indices[t + 2])};
        Vec2 p[3] = {{v[0][0], v[0][1]}, {v[1][0], v[1][1]}, {v[2][0], v[2][1]}};
        double area = orient(p[0], p[1], p[2]);
        if (area == 0) continue;
        if (area < 0) {
            std::swap(p[1], p[2]);
            std::swap(v[1], v[2]);
            area = -area;
        }
        int x0 = std::max(0, int(std::floor(std::min({p[0].x, p[1].x, p[2].x}))));
        int x1 = std::min(f.w - 1, int(std::ceil(std::max({p[0].x, p[1].x, p[2].x}))));
        int y0 = std::max(0, int(std::floor(std::min({p[0].y, p[1].y, p[2].y}))));
        int y1 = std::min(f.h - 1, int(std::ceil(std::max({p[0].y, p[1].y, p[2].y}))));
        for (int y = y0; y <= y1; ++y) {
            for (int x = x0; x <= x1; ++x) {
                Vec2 c{x + 0.5, y + 0.5};
                if (!inside(p[1], p[2], c) || !inside(p[2], p[0], c) || !inside(p[0], p[1], c)) continue;
                double w0 = orient(p[1], p[2], c) / area, w1 = orient(p[2], p[0], c) / area, w2 = 1 - w0 - w1;
                std::size_t px = std::size_t(y) * std::size_t(f.w) + std::size_t(x);
                double z = v[0][2]; // one element per triangle: one z
                if (depth_test && !(z > f.depth[px])) continue;
                Texel s = sample(img, w0 * v[0][3] + w1 * v[1][3] + w2 * v[2][3], w0 * v[0][4] + w1 * v[1][4] + w2 * v[2][4]);
                const double col[4] = {v[0][5], v[0][6], v[0][7], v[0][8]};
                double src[3] = {s.r * col[0], s.g * col[1], s.b * col[2]};
                double a = s.a * col[3];
                double* dst = &f.rgb[px * 3];
                if (d.pass == Pass::opaque) {
                    for (int k = 0; k < 3; ++k) dst[k] = src[k];
                    f.depth[px] = z;
                    continue;
                }
                for (int k = 0; k < 3; ++k) {
                    switch (d.blend) {
                    case Blend::alpha: dst[k] = src[k] * a + dst[k] * (1 - a); break;
                    case Blend::add: dst[k] = src[k] * a + dst[k]; break;
                    case Blend::multiply: dst[k] = src[k] * a * dst[k]; break;
                    case Blend::opaque: dst[k] = src[k]; break;
                    }
                }
            }
        }
    }
}

Frame render(const SceneMeshes& m, const std::vector<Image>& images) {
    Frame f;
    f.w = m.viewport.width;
    f.h = m.viewport.height;
    f.rgb.assign(std::size_t(f.w * f.h * 3), 0.25);
    f.depth.assign(std::size_t(f.w * f.h), 0.0);
    for (const Draw& d : m.draws) draw(f, d, images, m.depth_test);
    return f;
}

struct RandomScene {
    Scene scene;
    std::vector<Image> images;
    std::vector<ImageAnalysis> analyses;
    std::vector<const ImageAnalysis*> element_analysis;
};

RandomScene random_scene(std::uint64_t seed, int elements, const AnalyzeOptions& analyze = {}) {
    std::mt19937_64 rng(seed);
    RandomScene r;
    r.scene.viewport = {0, 0, 48, 48};
    const int images = 1 + int(rng() % 4);
    for (int k = 0; k < images; ++k) {
        ShapeParams p;
        p.width = 6 + int(rng() % 20);
        p.height = 6 + int(rng() % 20);
        p.blobs = 1 + int(rng() % 3);
        p.noise = rng() % 4 == 0;
        r.images.push_back(random_shape(seed * 131 + std::uint64_t(k), p));
        // Some images are solid (tiles): their opaque polygons cover all
        // they draw, so they skip the blend pass.
        if (rng() % 4 == 0)
            for (std::size_t t = 3; t < r.images.back().rgba.size(); t += 4) r.images.back().rgba[t] = 255;
        // Two entries name the same file for some images (tiles of a sheet).
        r.scene.images.push_back({"img" + std::to_string(k), "img" + std::to_string(k) + ".png", p.width, p.height});
    }
    r.analyses.reserve(std::size_t(elements));
    const double turns[4][4] = {{1, 0, 0, 1}, {0, 1, -1, 0}, {-1, 0, 0, -1}, {0, -1, 1, 0}};
    for (int i = 0; i < elements; ++i) {
        Element e;
        e.image = int(rng() % std::uint64_t(images));
        const Image& img = r.images[std::size_t(e.image)];
        // Sometimes a sub-rect (an atlas frame) rather than the whole image.
        if (rng() % 3 == 0) {
            int w = 3 + int(rng() % std::uint64_t(img.width - 2)), h = 3 + int(rng() % std::uint64_t(img.height - 2));
            w = std::min(w, img.width);
            h = std::min(h, img.height);
            e.rect = {int(rng() % std::uint64_t(img.width - w + 1)), int(rng() % std::uint64_t(img.height - h + 1)), w, h};
        } else {
            e.rect = img.view().bounds();
        }
        const double* t = turns[rng() % 4];
        double mirror = rng() % 4 == 0 ? -1 : 1;
        e.transform = {t[0] * mirror, t[1] * mirror, t[2], t[3], double(int(rng() % 90) - 20), double(int(rng() % 90) - 20)};
        const float tints[3] = {1.0f, 0.5f, 0.75f};
        e.color = {tints[rng() % 3], tints[rng() % 3], 1.0f, rng() % 4 == 0 ? 0.5f : 1.0f};
        const Blend blends[6] = {Blend::alpha, Blend::alpha, Blend::alpha, Blend::add, Blend::multiply, Blend::opaque};
        e.blend = blends[rng() % 6];
        r.scene.elements.push_back(e);
        r.analyses.push_back(analyze_image(img.view(), e.rect, analyze));
    }
    for (const ImageAnalysis& a : r.analyses) r.element_analysis.push_back(&a);
    return r;
}

// OpaqueMethod::cover's pieces (issue 25 point 2), as many as pay in these
// small images.
AnalyzeOptions cover_pieces() {
    AnalyzeOptions cover;
    cover.opaque.method = OpaqueMethod::cover;
    cover.opaque.max_polygons = 64;
    cover.opaque.min_area = 4;
    return cover;
}

void expect_same_frame(const Frame& a, const Frame& b, std::uint64_t seed, const char* what) {
    std::size_t diffs = 0, first = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
        if (a.rgb[i] != b.rgb[i] && diffs++ == 0) first = i / 3;
    }
    EXPECT_EQ(diffs, 0u) << what << ", seed " << seed << ": first differing pixel (" << first % std::size_t(a.w) << ", "
                         << first / std::size_t(a.w) << ")";
}

TEST(LookUnchanged, OptimizedFramesMatchOverpaintPixelForPixel) {
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        RandomScene r = random_scene(seed, 10 + int(seed % 50));
        const Frame plain = render(overpaint_meshes(r.scene), r.images);
        for (SortMethod sort : {SortMethod::batch, SortMethod::paper, SortMethod::none}) {
            for (GraphMode graph : {GraphMode::polygons, GraphMode::boxes}) {
                ReconstructOptions o;
                o.sort = sort;
                o.graph = graph;
                SceneMeshes m;
                ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m), ReconstructStatus::ok);
                expect_same_frame(plain, render(m, r.images), seed, "reconstruct_scene");
            }
        }
        ReconstructOptions cull;
        cull.cull_to_viewport = true;
        SceneMeshes culled;
        ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, cull, &culled), ReconstructStatus::ok);
        expect_same_frame(plain, render(culled, r.images), seed, "culled to the viewport");
        ReconstructOptions no_opaque;
        no_opaque.opaque_polygons = false;
        SceneMeshes m;
        ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, no_opaque, &m), ReconstructStatus::ok);
        expect_same_frame(plain, render(m, r.images), seed, "no opaque pass");
        ASSERT_EQ(rectangle_meshes(r.scene, {}, &m), ReconstructStatus::ok);
        expect_same_frame(plain, render(m, r.images), seed, "rectangle_meshes");
    }
}

// The scene reconstructed as is and with hidden parts clipped wherever
// anything is saved (clip_hidden with no price on triangles or edges).
bool reconstruct_clipped(const RandomScene& r, SceneMeshes* whole, SceneMeshes* cut) {
    ReconstructOptions o;
    if (reconstruct_scene(r.scene, r.element_analysis, o, whole) != ReconstructStatus::ok) return false;
    o.clip_hidden = {true, 1, 0, 0};
    return reconstruct_scene(r.scene, r.element_analysis, o, cut) == ReconstructStatus::ok;
}

// Issue 25: hidden parts clipped at opaque polygons in front (prices that
// clip wherever anything is saved) leave every frame as overpaint draws
// it, and do cut something: fewer fragments are rasterized.
TEST(LookUnchanged, ClippedHiddenPartsKeepTheFrame) {
    std::int64_t cut_scenes = 0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        RandomScene r = random_scene(seed, 10 + int(seed % 50));
        const Frame plain = render(overpaint_meshes(r.scene), r.images);
        SceneMeshes before, after;
        ASSERT_TRUE(reconstruct_clipped(r, &before, &after));
        expect_same_frame(plain, render(after, r.images), seed, "hidden parts clipped");
        const OverdrawStats a = analyze_overdraw(before), b = analyze_overdraw(after);
        EXPECT_LE(b.rasterized, a.rasterized) << "seed " << seed;
        cut_scenes += b.rasterized < a.rasterized;
    }
    EXPECT_GE(cut_scenes, 10);
}

// Every other element's analysis without its opaque polygons (copies
// kept in `store`).
std::vector<const ImageAnalysis*> without_opaque_every_other(const RandomScene& r, std::vector<ImageAnalysis>& store) {
    std::vector<const ImageAnalysis*> out = r.element_analysis;
    store.assign(out.size(), {});
    for (std::size_t i = 0; i < out.size(); i += 2) {
        store[i] = *out[i];
        store[i].opaque.clear();
        out[i] = &store[i];
    }
    return out;
}

// Every third element's boundary its whole rect (copies kept in `store`).
std::vector<const ImageAnalysis*> rect_boundary_every_third(const RandomScene& r, std::vector<ImageAnalysis>& store) {
    std::vector<const ImageAnalysis*> out = r.element_analysis;
    store.assign(out.size(), {});
    for (std::size_t i = 0; i < out.size(); i += 3) {
        store[i] = *out[i];
        store[i].boundary = {detail::rect_polygon(r.scene.elements[i].rect)};
        out[i] = &store[i];
    }
    return out;
}

// A frame made through a memo (which `use_memo` sets on the options)
// against the one made without it, byte for byte.
template <class UseMemo>
void expect_same_frame_with_memo(const RandomScene& r, const std::vector<const ImageAnalysis*>& analyses, ReconstructOptions o,
                                 UseMemo use_memo, std::uint64_t seed, int frame) {
    SceneMeshes fresh, kept;
    ASSERT_EQ(reconstruct_scene(r.scene, analyses, o, &fresh), ReconstructStatus::ok);
    use_memo(o);
    ASSERT_EQ(reconstruct_scene(r.scene, analyses, o, &kept), ReconstructStatus::ok);
    ASSERT_EQ(kept.draws.size(), fresh.draws.size()) << "seed " << seed << ", frame " << frame;
    for (std::size_t d = 0; d < fresh.draws.size(); ++d) {
        EXPECT_EQ(kept.draws[d].vertices, fresh.draws[d].vertices) << "seed " << seed << ", frame " << frame << ", draw " << d;
        EXPECT_EQ(kept.draws[d].indices, fresh.draws[d].indices) << "seed " << seed << ", frame " << frame << ", draw " << d;
        EXPECT_EQ(kept.draws[d].image, fresh.draws[d].image);
        EXPECT_EQ(kept.draws[d].pass, fresh.draws[d].pass);
    }
}

// Issue 25: choose_for_target keeps each element's last cut from one
// contestant frame to the next (ClipHiddenOptions::memo) and reuses it
// where the element is cut alike. Whatever came between (here frames
// alternating with every other element's opaque polygons dropped, so the
// elements behind them are cut differently), a frame made with the memo is
// byte for byte the one made without it.
TEST(LookUnchanged, ClipMemoGivesTheMeshesOfAFreshCut) {
    std::int64_t reused = 0;
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        RandomScene r = random_scene(seed, 10 + int(seed % 50));
        std::vector<ImageAnalysis> thinned;
        std::vector<const ImageAnalysis*> fewer = without_opaque_every_other(r, thinned);
        const auto memo = detail::make_clip_memo();
        int frame = 0;
        for (const auto* analyses : {&r.element_analysis, &fewer, &r.element_analysis, &r.element_analysis, &fewer}) {
            ReconstructOptions o;
            o.clip_hidden = {true, 1, 0, 0};
            expect_same_frame_with_memo(r, *analyses, o, [&](ReconstructOptions& m) { m.clip_hidden.memo = memo.get(); }, seed, frame++);
        }
        reused += detail::clip_memo_reused(*memo);
    }
    EXPECT_GT(reused, 0); // the memo was used, not only filled
}

// The chooser keeps the element graphs its contestant frames build
// (ReconstructOptions::graph_memo) and answers an equal build from them.
// Whatever came between (frames with other boundary polygons, opaque
// polygons dropped, without a depth buffer, which changes what the chain
// of a crowded cell links; a pair budget of 3 makes every cell crowded), a
// frame made with the memo is byte for byte the one made without it.
TEST(LookUnchanged, GraphMemoGivesTheMeshesOfAFreshGraph) {
    std::int64_t reused = 0;
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        RandomScene r = random_scene(seed, 10 + int(seed % 50));
        // Other boundary polygons, other opaque polygons: other graphs, then the same again.
        std::vector<ImageAnalysis> changed, thinned;
        std::vector<const ImageAnalysis*> rects = rect_boundary_every_third(r, changed), fewer = without_opaque_every_other(r, thinned);
        for (const std::uint64_t budget : {limits::kGraphPairBudget, std::uint64_t(3)}) {
            const auto memo = detail::make_graph_memo();
            int frame = 0;
            for (const auto* analyses : {&r.element_analysis, &rects, &fewer, &r.element_analysis, &rects, &r.element_analysis, &fewer})
                for (const bool depthless : {false, true}) {
                    ReconstructOptions o;
                    o.graph_pair_budget = budget;
                    o.depthless = depthless;
                    o.clip_hidden = {true, 1, 0, 0};
                    expect_same_frame_with_memo(r, *analyses, o, [&](ReconstructOptions& m) { m.graph_memo = memo.get(); }, seed, frame++);
                }
            reused += detail::graph_memo_reused(*memo);
        }
    }
    EXPECT_GT(reused, 0); // the memo was used, not only filled
}

// The same memo's contract on the graph itself: a build through it is the
// graph built afresh, for every `sorted` (which the chain of crowded cells
// reads) and boundary polygons, in any order of builds.
TEST(ElementGraphMemo, GivesTheGraphBuiltAfresh) {
    std::int64_t reused = 0;
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        RandomScene r = random_scene(seed, 10 + int(seed % 50));
        const std::size_t n = r.scene.elements.size();
        std::vector<ImageAnalysis> changed;
        std::vector<const ImageAnalysis*> rects = rect_boundary_every_third(r, changed);
        std::vector<std::uint8_t> odd(n, 0);
        for (std::size_t i = 1; i < n; i += 2) odd[i] = 1;
        const std::vector<std::uint8_t> none(n, 0);
        using Flags = const std::vector<std::uint8_t>*;
        for (const std::uint64_t budget : {limits::kGraphPairBudget, std::uint64_t(3)}) {
            const auto memo = detail::make_graph_memo();
            for (int round = 0; round < 2; ++round)
                for (const auto* analyses : {&r.element_analysis, &rects})
                    for (Flags sorted : {Flags(nullptr), Flags(&odd), Flags(&none)}) {
                        const detail::ElementShapes shapes = detail::element_shapes(r.scene, *analyses, true);
                        const ElementGraph fresh = detail::build_graph(r.scene, *analyses, shapes.boundary, GraphMode::polygons, sorted, budget);
                        const ElementGraph kept =
                            detail::build_graph(memo.get(), r.scene, *analyses, shapes.boundary, GraphMode::polygons, sorted, budget);
                        EXPECT_EQ(kept.offsets, fresh.offsets) << "seed " << seed;
                        EXPECT_EQ(kept.targets, fresh.targets) << "seed " << seed;
                        EXPECT_EQ(kept.chained, fresh.chained) << "seed " << seed;
                    }
            reused += detail::graph_memo_reused(*memo);
        }
    }
    EXPECT_GT(reused, 0);
}

// Issue 25: an occluder inside an element (touching none of its edges)
// leaves a ring, triangulated whole: on a tile GL snaps exactly 8
// triangles instead of two ear-clipped strips' 12; on a turned, scaled
// sprite (before: not cut at all, as strips would end on its outline)
// the ring is cut too. The frame is overpaint's either way.
TEST(LookUnchanged, OccludersInsideElementsLeaveRings) {
    for (const bool turned : {false, true}) {
        RandomScene r;
        r.scene.viewport = {0, 0, 64, 64};
        Image ground{32, 32, std::vector<std::uint8_t>(32 * 32 * 4, 0)};
        for (std::size_t t = 0; t < 32 * 32; ++t)
            ground.rgba[4 * t] = std::uint8_t(t * 7), ground.rgba[4 * t + 1] = std::uint8_t(t), ground.rgba[4 * t + 3] = turned ? 128 : 255;
        Image card{8, 8, std::vector<std::uint8_t>(8 * 8 * 4, 255)};
        for (std::size_t t = 0; t < 8 * 8; ++t) card.rgba[4 * t + 2] = std::uint8_t(t * 3);
        r.images = {ground, card};
        r.scene.images = {{"ground", "ground.png", 32, 32}, {"card", "card.png", 8, 8}};
        Element g;
        g.rect = {0, 0, 32, 32};
        g.transform = turned ? std::array<double, 6>{1.2 * std::cos(0.5), 1.2 * std::sin(0.5), -1.2 * std::sin(0.5), 1.2 * std::cos(0.5), 30.3, 6.7}
                             : std::array<double, 6>{1, 0, 0, 1, 16, 16};
        Element c;
        c.image = 1;
        c.rect = {0, 0, 8, 8};
        c.transform = {1.5, 0, 0, 1.5, 26, 26}; // inside the tile, 10 px from its edges (inside the turned one too)
        r.scene.elements = {g, c};
        r.analyses = {analyze_image(ground.view(), g.rect, {}), analyze_image(card.view(), c.rect, {})};
        for (const ImageAnalysis& a : r.analyses) r.element_analysis.push_back(&a);
        const Frame plain = render(overpaint_meshes(r.scene), r.images);
        SceneMeshes whole, cut;
        ASSERT_TRUE(reconstruct_clipped(r, &whole, &cut));
        expect_same_frame(plain, render(cut, r.images), turned, "a ring cut around an occluder");
        EXPECT_LT(analyze_overdraw(cut).rasterized, analyze_overdraw(whole).rasterized) << "turned " << turned;
        // The card's quad and the ring (4 + 4 points: 8 triangles).
        if (!turned) {
            EXPECT_EQ(cut.stats.triangles, 2 + 8);
        }
    }
}

// Issue 25: a tile drawn over a tile of the same cell, its opaque texels
// reaching three of its sides: its opaque polygon (kept half a texel
// inside by the analysis) reaches those sides, and the tile under it loses
// everything there, not all but thin rims: a band of 2 triangles is left of
// it (before: a ring of 8, rims 0.59 px wide), and the tile's own blend
// pass keeps only its clear columns. Flipped, turned by quarters and
// scaled by 2 as well; the frame is overpaint's.
TEST(LookUnchanged, TilesUnderTilesAreCutToTheirSides) {
    Image sheet{16, 8, std::vector<std::uint8_t>(16 * 8 * 4, 255)};
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x) {
            std::uint8_t* t = &sheet.rgba[std::size_t(4 * (y * 16 + x))];
            t[0] = std::uint8_t(x * 13), t[1] = std::uint8_t(y * 29), t[2] = std::uint8_t(40 + x * y);
            // The second tile: its two left columns clear or half clear.
            if (x >= 8 && x < 10) t[3] = (x + y) % 3 == 0 ? 128 : 0;
        }
    const std::array<std::array<double, 4>, 4> turns{{{1, 0, 0, 1}, {-1, 0, 0, 1}, {0, 1, -1, 0}, {2, 0, 0, -2}}};
    for (std::size_t k = 0; k < turns.size(); ++k) {
        RandomScene r;
        r.scene.viewport = {0, 0, 40, 40};
        r.images = {sheet};
        r.scene.images = {{"sheet", "sheet.png", 16, 8}};
        const auto& m = turns[k];
        // The cell's corner on whole pixels, wherever the turn puts the rect.
        const double cx = 20 - 4 * (m[0] + m[2]), cy = 20 - 4 * (m[1] + m[3]);
        Element ground, top;
        ground.rect = {0, 0, 8, 8};
        top.rect = {8, 0, 8, 8};
        ground.transform = top.transform = {m[0], m[1], m[2], m[3], cx, cy};
        r.scene.elements = {ground, top};
        AnalyzeOptions small;
        small.opaque.min_area = 4; // a tile of 8x8 texels
        r.analyses = {analyze_image(sheet.view(), ground.rect, small), analyze_image(sheet.view(), top.rect, small)};
        for (const ImageAnalysis& a : r.analyses) r.element_analysis.push_back(&a);
        const Frame plain = render(overpaint_meshes(r.scene), r.images);
        ReconstructOptions o;
        SceneMeshes m1;
        ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m1), ReconstructStatus::ok);
        expect_same_frame(plain, render(m1, r.images), k, "opaque polygons out to the rect's sides");
        o.clip_hidden = {true, 1, 0, 0};
        ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m1), ReconstructStatus::ok);
        expect_same_frame(plain, render(m1, r.images), k, "tiles under tiles cut to their sides");
        // The band left of the ground (2), the top tile's opaque polygon (2)
        // and what its blend pass draws beside that polygon (the clear
        // columns: 5 points, 3 triangles). Before: a ring of 8 left of the
        // ground, and the top tile's blend pass a ring of 9.
        EXPECT_EQ(m1.stats.triangles, 2 + 2 + 3) << "turn " << k;
    }
}

// Issue 25 point 2: the opaque pieces of OpaqueMethod::cover (many, meeting
// along texel rows, 1/16 texel inside the opaque texels) keep the frame,
// with and without hidden parts clipped at them, and hide more than the
// default's polygons: fewer blend-pass fragments are shaded in most scenes.
TEST(LookUnchanged, CoverPiecesKeepTheFrame) {
    const AnalyzeOptions cover = cover_pieces();
    int fewer = 0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        RandomScene r = random_scene(seed, 10 + int(seed % 50), cover);
        RandomScene d = random_scene(seed, 10 + int(seed % 50));
        const Frame plain = render(overpaint_meshes(r.scene), r.images);
        ReconstructOptions o;
        SceneMeshes m, by_default;
        ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m), ReconstructStatus::ok);
        expect_same_frame(plain, render(m, r.images), seed, "cover pieces");
        ASSERT_EQ(reconstruct_scene(d.scene, d.element_analysis, o, &by_default), ReconstructStatus::ok);
        const OverdrawStats a = analyze_overdraw(m), b = analyze_overdraw(by_default);
        fewer += a.shaded - a.shaded_opaque < b.shaded - b.shaded_opaque;
        o.clip_hidden = {true, 1, 0, 0};
        ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m), ReconstructStatus::ok);
        expect_same_frame(plain, render(m, r.images), seed, "cover pieces, hidden parts clipped");
    }
    EXPECT_GE(fewer, 20);
}

// Issue 25: opaque tiles cut from one sheet and laid out as in it (a
// backdrop), some flipped or scaled by 2 as a whole, some moved out of
// place, with a translucent sprite drawn among them (over the tiles drawn
// before it, under those after): merged into blocks, the frame is the same
// and mostly has fewer triangles.
TEST(LookUnchanged, MergedOpaqueTilesKeepTheFrame) {
    int fewer = 0, fewer_depthless = 0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        std::mt19937_64 rng(seed);
        RandomScene r;
        r.scene.viewport = {0, 0, 64, 48};
        Image sheet{16, 12, std::vector<std::uint8_t>(16 * 12 * 4, 255)};
        for (std::size_t t = 0; t < 16 * 12; ++t)
            for (int c = 0; c < 3; ++c) sheet.rgba[4 * t + std::size_t(c)] = std::uint8_t(rng() % 256);
        r.images.push_back(sheet);
        r.scene.images.push_back({"sheet", "sheet.png", 16, 12});
        const double scale = seed % 3 == 0 ? 2 : 1, flip = seed % 2 ? -1 : 1;
        const double ox = 20 + double(rng() % 8), oy = 10 + double(rng() % 8);
        for (int ty = 0; ty < 3; ++ty)
            for (int tx = 0; tx < 4; ++tx) {
                Element e;
                e.rect = {tx * 4, ty * 4, 4, 4};
                e.blend = rng() % 2 ? Blend::opaque : Blend::alpha;
                const double a = flip * scale, d = scale;
                const double shift = rng() % 5 == 0 ? 1 : 0; // out of place: not merged
                e.transform = {a, 0, 0, d, ox + a * e.rect.x + shift, oy + d * e.rect.y};
                r.scene.elements.push_back(e);
            }
        Element top;
        top.rect = {2, 2, 8, 8};
        top.transform = {1, 0, 0, 1, ox + 1, oy + 3};
        top.color = {1, 1, 1, 0.5f};
        r.scene.elements.insert(r.scene.elements.begin() + std::ptrdiff_t(rng() % (r.scene.elements.size() + 1)), top);
        for (const Element& e : r.scene.elements) r.analyses.push_back(analyze_image(sheet.view(), e.rect, {}));
        for (const ImageAnalysis& a : r.analyses) r.element_analysis.push_back(&a);
        const Frame plain = render(overpaint_meshes(r.scene), r.images);
        ReconstructOptions o;
        SceneMeshes apart, merged;
        ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &apart), ReconstructStatus::ok);
        o.merge_opaque = true;
        ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &merged), ReconstructStatus::ok);
        expect_same_frame(plain, render(merged, r.images), seed, "opaque tiles merged");
        EXPECT_LE(merged.stats.triangles, apart.stats.triangles) << "seed " << seed;
        fewer += merged.stats.triangles < apart.stats.triangles;
        EXPECT_EQ(analyze_overdraw(merged).shaded, analyze_overdraw(apart).shaded) << "seed " << seed;
        // Without a depth buffer a block is drawn at its leader's place in
        // painter's order: kept only where that order holds.
        o.depthless = true;
        SceneMeshes depthless;
        ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &depthless), ReconstructStatus::ok);
        EXPECT_FALSE(depthless.depth_test);
        expect_same_frame(plain, render(depthless, r.images), seed, "opaque tiles merged, no depth buffer");
        fewer_depthless += depthless.stats.triangles < apart.stats.triangles;
    }
    EXPECT_GE(fewer, 20);
    EXPECT_GE(fewer_depthless, 10);
}

// Issue 25: frames without a depth buffer (ReconstructOptions::depthless):
// the opaque pass back to front, and elements whose opaque polygons lie in
// front of another's blend-pass polygons drawing them blended instead. In
// random scenes (quarter turns, mirrors), with the default's polygons and
// with cover pieces, with and without hidden parts clipped, and with a pair
// budget so small that crowded spots chain: the frame is overpaint's and
// needs no depth buffer (and drawn with one, it is the same). In many
// scenes an opaque pass is left and in many an element moved its opaque
// polygons to the blend pass.
TEST(LookUnchanged, DepthlessFramesKeepTheFrame) {
    const AnalyzeOptions cover = cover_pieces();
    int kept = 0, moved = 0;
    for (std::uint64_t seed = 1; seed <= 30; ++seed)
        for (bool pieces : {false, true}) {
            RandomScene r = pieces ? random_scene(seed, 10 + int(seed % 50), cover) : random_scene(seed, 10 + int(seed % 50));
            const Frame plain = render(overpaint_meshes(r.scene), r.images);
            for (bool clip : {false, true})
                for (std::uint64_t budget : {limits::kGraphPairBudget, std::uint64_t(3)}) {
                    ReconstructOptions o;
                    if (clip) o.clip_hidden = {true, 1, 0, 0};
                    o.graph_pair_budget = budget;
                    o.merge_opaque = seed % 2 == 0;
                    SceneMeshes with_depth, m;
                    ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &with_depth), ReconstructStatus::ok);
                    o.depthless = true;
                    ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m), ReconstructStatus::ok);
                    EXPECT_FALSE(m.depth_test) << "seed " << seed;
                    expect_same_frame(plain, render(m, r.images), seed, clip ? "depthless, hidden parts clipped" : "depthless");
                    // Drawn with a depth buffer anyway, the same frame.
                    SceneMeshes tested = m;
                    tested.depth_test = true;
                    expect_same_frame(plain, render(tested, r.images), seed, "depthless meshes drawn with the depth test");
                    std::int64_t opaque[2] = {0, 0};
                    for (const SceneMeshes* x : {&with_depth, &m})
                        for (const Draw& d : x->draws)
                            if (d.pass == Pass::opaque) opaque[x == &m] += std::int64_t(d.triangle_count());
                    kept += opaque[1] > 0;
                    moved += opaque[1] < opaque[0];
                }
        }
    EXPECT_GE(kept, 100);
    EXPECT_GE(moved, 60);
}

// An opaque card in front of a translucent sprite: drawn in the opaque
// pass without depth, the sprite's blend pass would blend over it, so the
// card draws in the blend pass. A card beside the sprite keeps its opaque
// pass, and so does one whose only neighbour behind is opaque.
TEST(LookUnchanged, DepthlessCardsInFrontOfTranslucentSpritesBlend) {
    RandomScene r;
    r.scene.viewport = {0, 0, 40, 20};
    Image card{8, 8, std::vector<std::uint8_t>(8 * 8 * 4, 255)};
    for (std::size_t t = 0; t < 64; ++t) card.rgba[4 * t] = std::uint8_t(t * 3);
    r.images = {card};
    r.scene.images = {{"card", "card.png", 8, 8}};
    auto at = [&](double x, double y, float alpha) {
        Element e;
        e.rect = {0, 0, 8, 8};
        e.transform = {1, 0, 0, 1, x, y};
        e.color = {1, 1, 1, alpha};
        r.scene.elements.push_back(e);
    };
    at(2, 2, 0.5f);  // translucent sprite
    at(6, 6, 1.0f);  // card over it: moves to the blend pass
    at(20, 2, 1.0f); // a card alone
    at(24, 6, 1.0f); // a card over that card: keeps its opaque pass
    for (std::size_t i = 0; i < r.scene.elements.size(); ++i) r.analyses.push_back(analyze_image(card.view(), {0, 0, 8, 8}, {}));
    for (const ImageAnalysis& a : r.analyses) r.element_analysis.push_back(&a);
    ReconstructOptions o;
    o.depthless = true;
    SceneMeshes m;
    ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m), ReconstructStatus::ok);
    EXPECT_FALSE(m.depth_test);
    expect_same_frame(render(overpaint_meshes(r.scene), r.images), render(m, r.images), 0, "cards");
    std::int64_t opaque = 0, blend = 0;
    for (const Draw& d : m.draws) (d.pass == Pass::opaque ? opaque : blend) += std::int64_t(d.triangle_count());
    EXPECT_EQ(opaque, 4); // the two cards on the right
    EXPECT_EQ(blend, 4);  // the sprite and the card over it
}

// excess_overdraw sorts every fragment a frame shades, and what it calls
// needed is exactly what the ideal frame shades (these scenes have no pixel
// centre on a texel edge): for overpaint, the depth plan (rejected
// fragments uncounted), the plan with hidden parts clipped and the plan
// without a depth buffer (overlapping opaque pieces shade a pixel twice).
TEST(Overdraw, ExcessSortsEveryShadedFragmentAndNeedsTheIdealOnes) {
    const AnalyzeOptions cover = cover_pieces();
    std::int64_t transparent = 0, hidden = 0;
    for (std::uint64_t seed = 1; seed <= 20; ++seed) {
        RandomScene r = seed % 2 ? random_scene(seed, 10 + int(seed % 50), cover) : random_scene(seed, 10 + int(seed % 50));
        std::vector<ImageView> views;
        for (const Image& img : r.images) views.push_back(img.view());
        const OverdrawStats ideal_stats = ideal_overdraw(r.scene, views);
        const std::int64_t ideal = ideal_stats.shaded;
        std::vector<SceneMeshes> frames{overpaint_meshes(r.scene)};
        for (int plan = 0; plan < 3; ++plan) {
            ReconstructOptions o;
            if (plan >= 1) o.clip_hidden = {true, 1, 0, 0};
            o.depthless = plan == 2;
            ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &frames.emplace_back()), ReconstructStatus::ok);
        }
        for (std::size_t f = 0; f < frames.size(); ++f) {
            const ExcessStats e = excess_overdraw(frames[f], views);
            EXPECT_EQ(e.transparent + e.hidden + e.needed, analyze_overdraw(frames[f]).shaded) << "seed " << seed << ", frame " << f;
            EXPECT_EQ(e.needed, ideal) << "seed " << seed << ", frame " << f;
            // Every block a triangle shades holds a needed fragment or not.
            const OverdrawStats blocks = analyze_overdraw(frames[f], nullptr, true);
            EXPECT_EQ(e.blocks_needed + e.blocks_waste, blocks.blocks_opaque + blocks.blocks_blend) << "seed " << seed << ", frame " << f;
            if (f == 0) {
                // Overpaint draws each element as the limit's frame does, its
                // rect's two triangles: the blocks holding its needed
                // fragments are the ideal frame's.
                EXPECT_EQ(e.blocks_needed, ideal_stats.blocks_opaque + ideal_stats.blocks_blend) << "seed " << seed;
                transparent += e.transparent;
                hidden += e.hidden;
            }
        }
    }
    EXPECT_GT(transparent, 0); // the test sees both kinds
    EXPECT_GT(hidden, 0);
}

// The element graph's bound (docs/element-graph.md): with a pair budget
// too small for the scene, crowded cells keep painter's order; the frame
// must not change.
TEST(LookUnchanged, GraphPairBudgetNeverChangesTheFrame) {
    for (std::uint64_t seed = 1; seed <= 30; ++seed) {
        RandomScene r = random_scene(seed, 20 + int(seed % 40));
        const Frame plain = render(overpaint_meshes(r.scene), r.images);
        for (std::uint64_t budget : {0, 3, 40}) {
            for (SortMethod sort : {SortMethod::batch, SortMethod::paper}) {
                ReconstructOptions o;
                o.graph_pair_budget = budget;
                o.sort = sort;
                SceneMeshes m;
                ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m), ReconstructStatus::ok);
                expect_same_frame(plain, render(m, r.images), seed, "reconstruct_scene, small pair budget");
                o.opaque_polygons = false;
                ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m), ReconstructStatus::ok);
                expect_same_frame(plain, render(m, r.images), seed, "no opaque pass, small pair budget");
                ASSERT_EQ(rectangle_meshes(r.scene, o, &m), ReconstructStatus::ok);
                expect_same_frame(plain, render(m, r.images), seed, "rectangle_meshes, small pair budget");
            }
        }
    }
}

TEST(LookUnchanged, DynamicElementsDrawOnTop) {
    for (std::uint64_t seed = 100; seed < 110; ++seed) {
        RandomScene r = random_scene(seed, 30);
        // The last 8 elements move: the static scene is the rest.
        RandomScene stat = r;
        stat.scene.elements.resize(22);
        stat.element_analysis.resize(22);
        std::vector<Element> moving(r.scene.elements.begin() + 22, r.scene.elements.end());
        std::vector<const ImageAnalysis*> moving_analysis(r.element_analysis.begin() + 22, r.element_analysis.end());
        ReconstructOptions o;
        o.reserved_dynamic_levels = 8;
        SceneMeshes base, frame;
        ASSERT_EQ(reconstruct_scene(stat.scene, stat.element_analysis, o, &base), ReconstructStatus::ok);
        ASSERT_EQ(add_dynamic_elements(base, stat.scene, moving, moving_analysis, &frame), ReconstructStatus::ok);
        expect_same_frame(render(overpaint_meshes(r.scene), r.images), render(compose_frame(base, frame), r.images), seed, "dynamic");
    }
}

// Every vertex lies in a span naming the element map it samples through,
// and that map takes the vertex's screen position to its u, v: ids stay
// right however elements merge into draws, in every kind of output, skirts
// included.
void expect_consistent_maps(const SceneMeshes& m, const std::vector<TexelMap>& maps, const std::vector<Image>& images,
                            const char* what) {
    for (const Draw& d : m.draws) {
        ASSERT_FALSE(d.element_spans.empty()) << what;
        ASSERT_EQ(d.element_spans[0].first_vertex, 0u) << what;
        std::vector<std::uint32_t> vertex_elements(d.vertex_count());
        for (std::size_t k = 0; k < d.element_spans.size(); ++k) {
            const std::size_t end = k + 1 < d.element_spans.size() ? d.element_spans[k + 1].first_vertex : d.vertex_count();
            ASSERT_LE(d.element_spans[k].first_vertex, end) << what;
            for (std::size_t v = d.element_spans[k].first_vertex; v < end; ++v) vertex_elements[v] = d.element_spans[k].element;
        }
        const Image& img = images[std::size_t(d.image)];
        for (std::size_t i = 0; i < d.vertex_count(); ++i) {
            const std::uint32_t id = vertex_elements[i];
            ASSERT_LT(id, maps.size()) << what;
            const TexelMap& t = maps[id];
            const float* v = &d.vertices[i * kVertexFloats];
            EXPECT_NEAR(t.u0 + t.ux * v[0] + t.uy * v[1], double(v[3]) * img.width, 1e-3) << what << ", vertex " << i;
            EXPECT_NEAR(t.v0 + t.vx * v[0] + t.vy * v[1], double(v[4]) * img.height, 1e-3) << what << ", vertex " << i;
        }
        for (std::size_t t = 0; t + 3 <= d.indices.size(); t += 3) {
            EXPECT_EQ(vertex_elements[d.indices[t]], vertex_elements[d.indices[t + 1]]) << what;
            EXPECT_EQ(vertex_elements[d.indices[t]], vertex_elements[d.indices[t + 2]]) << what;
        }
    }
}

TEST(LookUnchanged, EveryVertexNamesItsElementMap) {
    for (std::uint64_t seed = 200; seed < 210; ++seed) {
        RandomScene r = random_scene(seed, 30);
        const std::vector<TexelMap> maps = element_maps(r.scene);
        ASSERT_EQ(maps.size(), r.scene.elements.size());
        expect_consistent_maps(overpaint_meshes(r.scene, 0, true), maps, r.images, "overpaint");
        expect_consistent_maps(overpaint_meshes(r.scene, 1.0 / 64, true), maps, r.images, "overpaint with skirts");
        for (const Draw& d : overpaint_meshes(r.scene).draws) EXPECT_TRUE(d.element_spans.empty()) << "not asked for";
        for (double margin : {0.0, 1.0 / 64}) {
            ReconstructOptions o;
            o.coverage_margin = margin;
            o.element_spans = true;
            SceneMeshes m;
            ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m), ReconstructStatus::ok);
            expect_consistent_maps(m, maps, r.images, "reconstruct_scene");
            ASSERT_EQ(rectangle_meshes(r.scene, o, &m), ReconstructStatus::ok);
            expect_consistent_maps(m, maps, r.images, "rectangle_meshes");
            o.element_spans = false;
            ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &m), ReconstructStatus::ok);
            for (const Draw& d : m.draws) EXPECT_TRUE(d.element_spans.empty()) << "not asked for";
        }
        // Dynamic elements' maps follow the static ones.
        RandomScene stat = r;
        stat.scene.elements.resize(22);
        stat.element_analysis.resize(22);
        std::vector<Element> moving(r.scene.elements.begin() + 22, r.scene.elements.end());
        std::vector<const ImageAnalysis*> moving_analysis(r.element_analysis.begin() + 22, r.element_analysis.end());
        ReconstructOptions o;
        o.reserved_dynamic_levels = 8;
        o.element_spans = true;
        SceneMeshes base, frame;
        ASSERT_EQ(reconstruct_scene(stat.scene, stat.element_analysis, o, &base), ReconstructStatus::ok);
        ASSERT_EQ(add_dynamic_elements(base, stat.scene, moving, moving_analysis, &frame, true), ReconstructStatus::ok);
        expect_consistent_maps(compose_frame(base, frame), maps, r.images, "dynamic");
    }
}

// Without a margin the output is what it always was: no skirt triangles.
TEST(LookUnchanged, NoCoverageMarginNoSkirt) {
    RandomScene r = random_scene(7, 20);
    SceneMeshes plain, grown;
    ReconstructOptions o;
    ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &plain), ReconstructStatus::ok);
    o.coverage_margin = 1.0 / 64;
    ASSERT_EQ(reconstruct_scene(r.scene, r.element_analysis, o, &grown), ReconstructStatus::ok);
    EXPECT_GT(grown.stats.triangles, plain.stats.triangles);
    EXPECT_EQ(overpaint_meshes(r.scene).stats.triangles, 2 * std::int64_t(r.scene.elements.size()));
}

} // namespace
} // namespace depthcull::test
