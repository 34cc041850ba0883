// FrameAssembler (depthcull/frame.h) and insertion points in the pure
// core: depth ranges, draw order and batching, statuses. Pixel identity is
// proven in the runtime (tests/runtime/test_frames.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>

#include "depthcull/frame.h"
#include "scene_fixtures.h"

#include "testing/count_allocations.h"

namespace depthcull {
namespace {

using test::SceneBuilder;

// Level of a vertex from its z (depth_z: blend (2k+1)/D, opaque (2k+2)/D).
std::int64_t level_of(float z, std::int64_t denominator) { return (std::int64_t(std::llround(double(z) * double(denominator))) - 1) / 2; }

struct Pictures {
    ImageAnalysis ball, block;
    FrameAssembler assembler;
    int ball_id = -1, block_id = -1;
    explicit Pictures(const AssemblerOptions& options = {}) : assembler(options) {
        // A 16x16 picture: boundary its rect, an opaque core.
        ball.rect = block.rect = {0, 0, 16, 16};
        ball.boundary = {{{0, 0}, {16, 0}, {16, 16}, {0, 16}}};
        ball.opaque = {{{4, 4}, {12, 4}, {12, 12}, {4, 12}}};
        ball.stats.nontransparent_texels = 256;
        ball.stats.opaque_covered_texels = 64;
        block = ball;
        EXPECT_EQ(assembler.add_image({0, 16, 16, ball.rect, &ball}, &ball_id), FrameStatus::ok);
        EXPECT_EQ(assembler.add_image({1, 16, 16, block.rect, &block}, &block_id), FrameStatus::ok);
    }
};

Sprite at(int image, double x, double y) {
    Sprite s;
    s.image = image;
    s.transform = {1, 0, 0, 1, x, y};
    return s;
}

TEST(FrameAssembler, SpritesOfOneTextureShareOneBlendDrawEvenWhenStacked) {
    Pictures p;
    std::vector<Sprite> sprites;
    for (int i = 0; i < 1000; ++i) sprites.push_back(at(p.ball_id, 100 + (i % 7), 100 + (i % 5)));
    AssembledFrame frame;
    ASSERT_EQ(p.assembler.assemble(sprites, {0, 0, 640, 480}, &frame), FrameStatus::ok);
    EXPECT_EQ(frame.stats.blend_batches, 1);
    EXPECT_EQ(frame.stats.opaque_draws, 1);
    // Painter's order within the draw: levels ascend.
    const FrameDraw& d = frame.draws.back();
    std::int64_t last = -1;
    for (std::uint32_t k = d.first_index; k < d.first_index + d.index_count; ++k) {
        const std::int64_t level = level_of(frame.vertices[std::size_t(frame.indices[k]) * kVertexFloats + 2], frame.depth_denominator);
        EXPECT_GE(level, last);
        last = level;
    }
}

TEST(FrameAssembler, OverlappingTexturesKeepPainterOrderDisjointOnesBatch) {
    Pictures p;
    std::vector<Sprite> stacked, apart;
    for (int i = 0; i < 100; ++i) {
        stacked.push_back(at(i % 2 ? p.block_id : p.ball_id, 50, 50));
        apart.push_back(at(i % 2 ? p.block_id : p.ball_id, i % 2 ? 300 : 20, 20 + 2 * i));
    }
    AssembledFrame frame;
    ASSERT_EQ(p.assembler.assemble(stacked, {0, 0, 640, 480}, &frame), FrameStatus::ok);
    EXPECT_EQ(frame.stats.blend_batches, 100);
    ASSERT_EQ(p.assembler.assemble(apart, {0, 0, 640, 480}, &frame), FrameStatus::ok);
    EXPECT_EQ(frame.stats.blend_batches, 2);
}

TEST(FrameAssembler, PastTheCellBudgetBatchingDegradesOrderHolds) {
    AssemblerOptions options;
    options.cell_budget = 0; // every sprite counts as overlapping every other
    Pictures p(options);
    std::vector<Sprite> apart;
    for (int i = 0; i < 100; ++i) apart.push_back(at(i % 2 ? p.block_id : p.ball_id, i % 2 ? 300 : 20, 20 + 2 * i));
    AssembledFrame frame;
    ASSERT_EQ(p.assembler.assemble(apart, {0, 0, 640, 480}, &frame), FrameStatus::ok);
    EXPECT_EQ(frame.stats.blend_batches, 100);
    EXPECT_EQ(frame.stats.over_budget, 100);
}

// Issue 21's rect edges (needs_rect_edges in shapes.cpp), per sprite: a
// sprite GL snaps whose picture's edges bleed draws its whole rect in the
// blend pass, from overpaint's four corners and no skirt, as the static
// reconstruction draws such an element; its opaque polygons stay. A sprite
// that snaps exactly, or whose picture does not bleed, keeps its polygons.
TEST(FrameAssembler, TurnedOrScaledSpritesOfBleedingPicturesDrawTheirRect) {
    ImageAnalysis octagon;
    octagon.rect = {0, 0, 16, 16};
    octagon.boundary = {{{4, 0}, {12, 0}, {16, 4}, {16, 12}, {12, 16}, {4, 16}, {0, 12}, {0, 4}}};
    octagon.opaque = {{{4, 4}, {12, 4}, {12, 12}, {4, 12}}};
    octagon.stats.nontransparent_texels = 224;
    octagon.stats.opaque_covered_texels = 64;
    ImageAnalysis bleeding = octagon;
    bleeding.bleeding_edges = true;
    FrameAssembler assembler;
    int plain_id = -1, bleeding_id = -1;
    ASSERT_EQ(assembler.add_image({0, 16, 16, octagon.rect, &octagon}, &plain_id), FrameStatus::ok);
    ASSERT_EQ(assembler.add_image({0, 16, 16, bleeding.rect, &bleeding}, &bleeding_id), FrameStatus::ok);
    auto blend_vertices = [&](int image, const std::array<double, 6>& transform, AssembledFrame& frame) {
        Sprite s;
        s.image = image;
        s.transform = transform;
        EXPECT_EQ(assembler.assemble(std::span<const Sprite>(&s, 1), {0, 0, 640, 480}, &frame), FrameStatus::ok);
        EXPECT_EQ(frame.stats.opaque_draws, 1);
        std::vector<Vec2> v;
        const FrameDraw& d = frame.draws.back();
        EXPECT_EQ(d.pass, Pass::blend);
        for (std::uint32_t k = d.first_index; k < d.first_index + d.index_count; ++k) {
            const float* p = &frame.vertices[std::size_t(frame.indices[k]) * kVertexFloats];
            v.push_back({p[0], p[1]});
        }
        return v;
    };
    const std::array<double, 6> scaled{0.3, 0, 0, 0.3, 10.3, 20.7}, tile{1, 0, 0, 1, 10, 20};
    AssembledFrame frame;
    const std::vector<Vec2> rect = blend_vertices(bleeding_id, scaled, frame);
    ASSERT_EQ(rect.size(), 6u); // one quad, no skirt
    for (const Vec2& p : rect) {
        const double u = (p.x - 10.3) / 0.3, v = (p.y - 20.7) / 0.3;
        EXPECT_TRUE(std::abs(u) < 1e-3 || std::abs(u - 16) < 1e-3) << u;
        EXPECT_TRUE(std::abs(v) < 1e-3 || std::abs(v - 16) < 1e-3) << v;
    }
    EXPECT_GT(blend_vertices(plain_id, scaled, frame).size(), 6u);   // polygons and their texel skirt
    EXPECT_GT(blend_vertices(bleeding_id, tile, frame).size(), 6u);  // snaps exactly: polygons
}

// Issue 23: once warmed up (here by reserve()), frames allocate nothing,
// fully dynamic or at insertion points, whatever the sprites do: turn,
// scale from 1/64 (the wider texel-margin templates) to 2, flip, animate,
// change blend and alpha, move off screen, or pile up past the cell budget.
TEST(FrameAssembler, FramesAllocateNothingAfterWarmUp) {
    ImageAnalysis octagon, notched;
    octagon.rect = {0, 0, 16, 16};
    octagon.boundary = {{{4, 0}, {12, 0}, {16, 4}, {16, 12}, {12, 16}, {4, 16}, {0, 12}, {0, 4}}};
    octagon.opaque = {{{4, 4}, {12, 4}, {12, 12}, {4, 12}}};
    octagon.stats.nontransparent_texels = 224;
    octagon.stats.opaque_covered_texels = 64;
    notched = octagon; // a reflex corner: polygon and joined skirt
    notched.rect = {16, 0, 16, 16};
    notched.boundary = {{{17, 1}, {31, 1}, {31, 15}, {24, 8}, {17, 15}}};
    notched.opaque = {};
    FrameAssembler assembler;
    int ids[3] = {-1, -1, -1}, animation = -1;
    ASSERT_EQ(assembler.add_image({0, 32, 16, octagon.rect, &octagon}, &ids[0]), FrameStatus::ok);
    ASSERT_EQ(assembler.add_image({0, 32, 16, notched.rect, &notched}, &ids[1]), FrameStatus::ok);
    ASSERT_EQ(assembler.add_image({1, 16, 16, octagon.rect, &octagon}, &ids[2]), FrameStatus::ok);
    ASSERT_EQ(assembler.add_animation(ids, &animation), FrameStatus::ok);
    SceneBuilder b;
    const int img = b.image("a", 16, 16);
    const ImageAnalysis* full = b.full(img);
    for (int i = 0; i < 6; ++i) b.add(img, full, 10 + 40 * i, 10);
    ReconstructOptions options;
    options.insertion_points = {{2, 1000}, {4, 1000}};
    SceneMeshes meshes;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, options, &meshes), ReconstructStatus::ok);

    std::vector<Sprite> sprites(1500);
    auto move = [&](int frame) {
        for (std::size_t i = 0; i < sprites.size(); ++i) {
            Sprite& s = sprites[i];
            const std::size_t k = i * 7 + std::size_t(frame) * 3;
            s.image = ids[k % 3];
            s.animation = k % 5 == 0 ? animation : -1;
            s.frame = int(k % 4);
            const double a = 0.01 * double(i) + 0.3 * frame, scale = std::ldexp(1.0, -int(k % 8)) * 2; // 2 .. 1/64
            const double flip = k % 3 == 0 ? -1 : 1, stretch = k % 4 == 0 ? 0.3 : 1;
            s.transform = {flip * scale * std::cos(a), flip * scale * std::sin(a), -stretch * scale * std::sin(a),
                           stretch * scale * std::cos(a), double(k % 700) - 30, double((i * 53) % 520) - 20};
            if (k % 9 == 0) s.transform = {1, 0, 0, 1, double(k % 640), 8}; // snaps exactly
            s.blend = std::array<Blend, 4>{Blend::alpha, Blend::add, Blend::multiply, Blend::opaque}[k % 4];
            s.color = {1, 1, 1, k % 6 == 0 ? 0.5f : 1.0f};
        }
    };
    const Viewport view{0, 0, 640, 480};
    AssembledFrame frame;
    assembler.reserve(sprites.size(), &frame);
    const std::span<const Sprite> all(sprites);
    const std::vector<std::span<const Sprite>> lists{all.subspan(0, 700), all.subspan(700)};
    const std::int64_t before = g_allocations.load();
    for (int f = 0; f < 6; ++f) {
        move(f);
        ASSERT_EQ(assembler.assemble(sprites, view, &frame), FrameStatus::ok);
        ASSERT_EQ(assembler.assemble_at(meshes, lists, view, &frame), FrameStatus::ok);
    }
    EXPECT_EQ(g_allocations.load() - before, 0);
    EXPECT_EQ(frame.points.size(), 2u);
    EXPECT_GT(frame.stats.opaque_draws, 0);
}

// A frame whose vertices outgrow the caches streams them (frame_assembler.cpp,
// kStreamBytes: decided from the frame before): the same vertices, indices
// and draws as a frame written through the cache.
TEST(FrameAssembler, BigFramesStreamTheSameFrame) {
    Pictures p;
    std::vector<Sprite> sprites;
    for (int i = 0; i < 60000; ++i) {
        Sprite s = at(i % 2 ? p.block_id : p.ball_id, double((i * 37) % 1900) + 0.3, double((i * 53) % 1000) + 0.7);
        const double a = 0.001 * i, scale = 0.5 + (i % 7) * 0.25;
        s.transform = {scale * std::cos(a), scale * std::sin(a), -scale * std::sin(a), scale * std::cos(a), s.transform[4], s.transform[5]};
        if (i % 5 == 0) s.color[3] = 0.5f;
        sprites.push_back(s);
    }
    AssembledFrame cached, streamed;
    ASSERT_EQ(p.assembler.assemble(sprites, {0, 0, 1920, 1080}, &cached), FrameStatus::ok);
    ASSERT_GT(cached.vertices.size() * sizeof(float), std::size_t(8) << 20); // big enough to stream next time
    ASSERT_EQ(p.assembler.assemble(sprites, {0, 0, 1920, 1080}, &streamed), FrameStatus::ok); // first: cached
    ASSERT_EQ(p.assembler.assemble(sprites, {0, 0, 1920, 1080}, &streamed), FrameStatus::ok); // streamed
    EXPECT_TRUE(std::equal(cached.vertices.begin(), cached.vertices.end(), streamed.vertices.begin(), streamed.vertices.end()));
    EXPECT_TRUE(std::equal(cached.indices.begin(), cached.indices.end(), streamed.indices.begin(), streamed.indices.end()));
    ASSERT_EQ(cached.draws.size(), streamed.draws.size());
    for (std::size_t i = 0; i < cached.draws.size(); ++i) {
        EXPECT_EQ(cached.draws[i].first_index, streamed.draws[i].first_index);
        EXPECT_EQ(cached.draws[i].index_count, streamed.draws[i].index_count);
    }
}

TEST(FrameAssembler, BadInputGetsAStatus) {
    Pictures p;
    int id = -1;
    EXPECT_EQ(p.assembler.add_image({0, 8, 8, {0, 0, 16, 16}, &p.ball}, &id), FrameStatus::bad_image);
    EXPECT_EQ(p.assembler.add_image({0, 16, 16, {0, 0, 16, 16}, nullptr}, &id), FrameStatus::bad_image);
    AssembledFrame frame;
    std::vector<Sprite> sprites{at(7, 0, 0)};
    EXPECT_EQ(p.assembler.assemble(sprites, {0, 0, 64, 64}, &frame), FrameStatus::bad_sprite);
    sprites = {at(p.ball_id, NAN, 0)};
    EXPECT_EQ(p.assembler.assemble(sprites, {0, 0, 64, 64}, &frame), FrameStatus::bad_sprite);
    sprites = {at(p.ball_id, 0, 0)};
    sprites[0].animation = 3;
    EXPECT_EQ(p.assembler.assemble(sprites, {0, 0, 64, 64}, &frame), FrameStatus::bad_sprite);
}

// The largest transform a sprite may have (kMaxCoordinate) overlaps
// every cell, as it may draw anywhere. (Before sprites took an element's
// ranges, 1e308 made an inf - inf screen box, once cast to int from NaN.)
TEST(FrameAssembler, HugeTransformsOverlapTheWholeGrid) {
    Pictures p;
    AssembledFrame frame;
    std::vector<Sprite> sprites{at(p.ball_id, 10, 10), at(p.block_id, 0, 0), at(p.ball_id, 600, 400)};
    sprites[1].transform = {1e9, 1e9, -1e9, 1e9, 1e9, -1e9};
    ASSERT_EQ(p.assembler.assemble(sprites, {0, 0, 640, 480}, &frame), FrameStatus::ok);
    // The far ball may not join the first one's draw across it.
    EXPECT_EQ(frame.stats.blend_batches, 3);
    for (float v : frame.vertices) EXPECT_TRUE(std::isfinite(v));
}

// Sprites take an element's ranges (scene JSON, dc_scene_add_element):
// transform values within +-1e9, colours in 0..1. Beyond them a vertex
// was Infinity (1e300, or a scale of 1e39 made a float), or a colour went
// into the vertices as it was (5, -1). problem() names sprite and field.
TEST(FrameAssembler, OutOfRangeSpritesAreRefusedByField) {
    Pictures p;
    AssembledFrame frame;
    struct Case {
        int transform = -1, color = -1;
        double value;
    };
    for (const Case c : {Case{4, -1, 1e300}, Case{0, -1, 1e39}, Case{5, -1, -1.5e9}, Case{1, -1, NAN}, Case{-1, 0, 5}, Case{-1, 3, -1},
                         Case{-1, 2, INFINITY}}) {
        std::vector<Sprite> sprites{at(p.ball_id, 0, 0), at(p.ball_id, 4, 4), at(p.block_id, 8, 8)};
        Sprite& bad = sprites[1];
        if (c.transform >= 0) bad.transform[std::size_t(c.transform)] = c.value;
        else bad.color[std::size_t(c.color)] = float(c.value);
        ASSERT_EQ(p.assembler.assemble(sprites, {0, 0, 64, 64}, &frame), FrameStatus::bad_sprite) << c.value;
        const FrameProblem& problem = p.assembler.problem();
        EXPECT_EQ(problem.point, -1);
        EXPECT_EQ(problem.item, 1);
        EXPECT_STREQ(problem.field, c.transform >= 0 ? "transform" : "color");
        EXPECT_EQ(problem.component, c.transform >= 0 ? c.transform : c.color);
        EXPECT_TRUE(problem.has_value);
        if (!std::isnan(c.value)) {
            EXPECT_EQ(problem.value, c.transform >= 0 ? c.value : double(float(c.value)));
        }
        EXPECT_TRUE(frame.vertices.empty());
    }
    // The edges of the ranges are accepted.
    std::vector<Sprite> edge{at(p.ball_id, 1e9, -1e9)};
    edge[0].transform[0] = -1e9;
    edge[0].color = {0, 1, 0, 1};
    EXPECT_EQ(p.assembler.assemble(edge, {0, 0, 64, 64}, &frame), FrameStatus::ok);
}

TEST(FrameAssembler, RefusalsSayWhy) {
    Pictures p;
    int id = -1;
    // An analysis of another rect: its polygons would be drawn at that rect's place.
    ImageAnalysis other = p.ball;
    other.rect = {0, 0, 8, 8};
    EXPECT_EQ(p.assembler.add_image({0, 16, 16, {0, 0, 16, 16}, &other}, &id), FrameStatus::bad_image);
    EXPECT_STREQ(p.assembler.problem().field, "analysis");
    EXPECT_EQ(p.assembler.add_image({0, 16, 16, {0, 0, 0, 16}, &p.ball}, &id), FrameStatus::bad_image);
    EXPECT_STREQ(p.assembler.problem().field, "rect");
    EXPECT_EQ(p.assembler.image_count(), 2u);
    // Animations: no frames, or a frame that is no picture.
    EXPECT_EQ(p.assembler.add_animation({}, &id), FrameStatus::bad_image);
    EXPECT_STREQ(p.assembler.problem().field, "frames");
    const int frames[] = {p.ball_id, 7};
    EXPECT_EQ(p.assembler.add_animation(frames, &id), FrameStatus::bad_image);
    EXPECT_STREQ(p.assembler.problem().field, "image");
    EXPECT_EQ(p.assembler.problem().item, 1);
    EXPECT_EQ(p.assembler.problem().value, 7);
    // Reserving past a frame's most sprites allocates nothing.
    AssembledFrame frame;
    EXPECT_EQ(p.assembler.reserve(SIZE_MAX, &frame), FrameStatus::too_many_sprites);
    EXPECT_EQ(p.assembler.reserve(std::size_t(1) << 40, &frame), FrameStatus::too_many_sprites);
    EXPECT_STREQ(p.assembler.problem().field, "sprites");
    EXPECT_EQ(frame.vertices.capacity(), 0u);
    EXPECT_EQ(p.assembler.reserve(16, &frame), FrameStatus::ok);
    // A sprite's unknown picture, animation and blend.
    std::vector<Sprite> sprites{at(p.ball_id, 0, 0), at(9, 0, 0)};
    EXPECT_EQ(p.assembler.assemble(sprites, {0, 0, 64, 64}, &frame), FrameStatus::bad_sprite);
    EXPECT_STREQ(p.assembler.problem().field, "image");
    EXPECT_EQ(p.assembler.problem().item, 1);
    sprites[1] = at(p.ball_id, 0, 0);
    sprites[1].animation = 3;
    EXPECT_EQ(p.assembler.assemble(sprites, {0, 0, 64, 64}, &frame), FrameStatus::bad_sprite);
    EXPECT_STREQ(p.assembler.problem().field, "animation");
    sprites[1].animation = -1;
    sprites[1].blend = Blend(9);
    EXPECT_EQ(p.assembler.assemble(sprites, {0, 0, 64, 64}, &frame), FrameStatus::bad_sprite);
    EXPECT_STREQ(p.assembler.problem().field, "blend");
}

// A static scene with an insertion point: elements before it keep levels
// below the reserved range, those after it lie above it, and no static
// blend draw spans the point.
TEST(InsertionPoints, ReserveARangeBetweenTheLayers) {
    SceneBuilder b;
    const int img = b.image("a", 16, 16);
    const ImageAnalysis* a = b.full(img);
    for (int i = 0; i < 6; ++i) b.add(img, a, 10 + 40 * i, 10); // disjoint: all level 0 without a point
    ReconstructOptions options;
    options.insertion_points = {{3, 5}};
    options.element_spans = true;
    SceneMeshes m;
    ASSERT_EQ(reconstruct_scene(b.scene, b.analyses, options, &m), ReconstructStatus::ok);
    ASSERT_EQ(m.insertion_points.size(), 1u);
    const InsertionPoint& point = m.insertion_points[0];
    EXPECT_EQ(point.first_level, 1);
    EXPECT_EQ(m.stats.depth_levels, 1 + 5 + 1);
    for (std::size_t k = 0; k < m.draws.size(); ++k) {
        const Draw& d = m.draws[k];
        for (const ElementSpan& span : d.element_spans) {
            const std::int64_t level = level_of(d.vertices[std::size_t(span.first_vertex) * kVertexFloats + 2], m.depth_denominator);
            if (span.element < 3) EXPECT_LT(level, point.first_level);
            else EXPECT_GE(level, point.first_level + point.levels);
            if (d.pass == Pass::blend) {
                EXPECT_EQ(k < point.blend_draw, span.element < 3) << "draw " << k;
            }
        }
    }
    // Without the point the six share one draw; with it, one each side.
    EXPECT_EQ(m.stats.draw_calls, 2);

    // Sprites at the point take levels in its range; more than it holds: a status.
    Pictures p;
    std::vector<Sprite> sprites{at(p.ball_id, 0, 0), at(p.ball_id, 5, 5)};
    std::vector<std::span<const Sprite>> lists{sprites};
    AssembledFrame frame;
    ASSERT_EQ(p.assembler.assemble_at(m, lists, {0, 0, 256, 256}, &frame), FrameStatus::ok);
    ASSERT_EQ(frame.points.size(), 1u);
    EXPECT_EQ(frame.points[0].static_draw, point.blend_draw);
    for (std::size_t v = 2; v < frame.vertices.size(); v += kVertexFloats) {
        const std::int64_t level = level_of(frame.vertices[v], m.depth_denominator);
        EXPECT_GE(level, point.first_level);
        EXPECT_LT(level, point.first_level + point.levels);
    }
    std::vector<Sprite> many(6, at(p.ball_id, 0, 0));
    lists = {many};
    EXPECT_EQ(p.assembler.assemble_at(m, lists, {0, 0, 256, 256}, &frame), FrameStatus::too_many_sprites);
    EXPECT_EQ(p.assembler.problem().point, 0);
    // A sprite out of range at a point: named by point and place in its list.
    sprites[1].color[1] = 2;
    lists = {sprites};
    EXPECT_EQ(p.assembler.assemble_at(m, lists, {0, 0, 256, 256}, &frame), FrameStatus::bad_sprite);
    EXPECT_EQ(p.assembler.problem().point, 0);
    EXPECT_EQ(p.assembler.problem().item, 1);
    EXPECT_STREQ(p.assembler.problem().field, "color");
    EXPECT_EQ(p.assembler.problem().component, 1);
    options.insertion_points = {{7, 1}};
    EXPECT_EQ(reconstruct_scene(b.scene, b.analyses, options, &m), ReconstructStatus::invalid_scene);
}

} // namespace
} // namespace depthcull
