// depthcull: moving sprites depth-culled every frame (beyond the paper:
// section 4, caveat 2). A FrameAssembler turns each frame's sprites, in
// painter's order, into depth values, an opaque pass (front to back, depth
// writes) and a blend pass batched by texture wherever the overlap allows,
// from per-image polygons analysed once (asset build or load time).
//
// Two uses:
// - fully dynamic frames (a sprite batch, no static scene): assemble();
// - sprites between the layers of a static scene reconstructed with
//   insertion points (ReconstructOptions::insertion_points): assemble_at().
//   The static meshes reserve a range of depth levels at each point; the
//   sprites of a point take levels in that range, so static elements behind
//   the point stay behind them and those in front stay in front; the point's
//   blend draws go between the static blend draws behind and in front.
//
// Pure core: no I/O, no threads, no exceptions; failures are status values.
// After warm-up (or reserve()), a frame allocates nothing: every buffer
// keeps its capacity from frame to frame.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <new>
#include <optional>
#include <utility>
#include <span>
#include <vector>

#include "depthcull/analyze.h"
#include "depthcull/scene.h"

namespace depthcull {

// One picture a sprite can show: a rect of a texture (an atlas frame or a
// whole image) and its analysis.
struct SpriteImage {
    int texture = 0;                  // what Draw/FrameDraw::image names (the renderer's texture index)
    int texture_width = 0, texture_height = 0;
    Rect rect;                        // texels of the texture this picture shows
    const ImageAnalysis* analysis = nullptr; // of `rect` (copied into templates; need not outlive add_image)
};

// One moving sprite of a frame.
struct Sprite {
    int image = 0;      // FrameAssembler::add_image id, or with animation >= 0 ignored
    int animation = -1; // FrameAssembler::add_animation id, or -1
    int frame = 0;      // animation frame (taken modulo its frame count)
    // As Element::transform: screen = (a*u + c*v + e, b*u + d*v + f), (u, v)
    // texels of the rect with its top-left at the origin. Each value finite
    // and within +-limits::kMaxCoordinate, as an element's.
    std::array<double, 6> transform{1, 0, 0, 1, 0, 0};
    std::array<float, 4> color{1, 1, 1, 1}; // each in 0..1, as an element's
    Blend blend = Blend::alpha;
};

enum class FrameStatus {
    ok,
    bad_image,        // add_image: empty rect, rect outside the texture, no analysis or one of another rect, negative
                      // texture; add_animation: no frames, or a frame that is no add_image id
    bad_sprite,       // a sprite names an unknown image or animation, or a transform value or colour is out of range
    too_many_sprites, // more sprites than depth levels (kMaxDepthLevels, or an insertion point's reserved levels)
    bad_meshes,       // assemble_at: static meshes without insertion points, or fewer than the sprite lists
};

// What a FrameAssembler call that did not return ok was refused for,
// beyond its status, for a front end's message ("sprite 3: transform[4]
// 1e+300 is not a finite number within +-1e9"): the status alone cannot
// say which of a frame's sprites, or which of its fields. Static text, so
// a refused frame allocates nothing either.
struct FrameProblem {
    std::int64_t point = -1;     // assemble_at: the sprite list (insertion point) at fault; -1 otherwise
    std::int64_t item = -1;      // the sprite within its list, or add_animation's frame; -1 when no one item is
    const char* field = "";      // "transform", "color", "image", "animation", "blend", "rect", "analysis", ...; "" none
    int component = -1;          // transform[component] or color[component]; -1 otherwise
    bool has_value = false;      // whether `value` is the value at fault:
    double value = 0;            // the component's value, the id or the count (frames, sprites) at fault
    const char* reason = "";     // why, e.g. "is not a finite number within +-1e9 (kMaxCoordinate)"
};

// A draw of an assembled frame: `index_count` indices from `first_index`
// of AssembledFrame::indices, which index AssembledFrame::vertices
// (kVertexFloats each) directly.
struct FrameDraw {
    int image = 0; // texture
    Pass pass = Pass::blend;
    Blend blend = Blend::alpha;
    std::uint32_t first_index = 0, index_count = 0;
};

// Where an insertion point's blend draws go: after the static blend draws
// before static draw `static_draw` (an index into SceneMeshes::draws; the
// static draws from there on are drawn after them), the frame's blend draws
// [first_draw, end_draw).
struct FramePoint {
    std::uint32_t static_draw = 0;
    std::uint32_t first_draw = 0, end_draw = 0;
};

struct FrameStats {
    std::int64_t sprites = 0;
    std::int64_t draw_calls = 0;    // the frame's own draws (opaque + blend)
    std::int64_t opaque_draws = 0;
    std::int64_t triangles = 0;
    std::int64_t blend_batches = 0; // blend draws
    // Sprites whose screen box covered more grid cells than
    // AssemblerOptions::cell_budget: treated as overlapping every sprite
    // (correct, less batching).
    std::int64_t over_budget = 0;
};

// An allocator whose resize() leaves new floats and indices uninitialized:
// assembly writes every one right after, and zero-filling first would
// double the memory traffic of a frame (most of its cost).
template <class T>
struct UninitializedAllocator : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = UninitializedAllocator<U>;
    };
    UninitializedAllocator() = default;
    template <class U>
    UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... Args>
    void construct(U* p, Args&&... args) {
        ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
    }
};

// One frame's draws: draws[0, opaque_draws) are the opaque pass (front to
// back), the rest blend draws grouped by insertion point (points). Buffers
// keep their capacity between frames: reuse one AssembledFrame. Vertices
// lie in painter's order, sprite by sprite, in groups of 4 per template
// (a few padding copies that no index names): draws index them anywhere.
struct AssembledFrame {
    std::vector<float, UninitializedAllocator<float>> vertices;          // kVertexFloats per vertex
    std::vector<std::uint32_t, UninitializedAllocator<std::uint32_t>> indices;
    std::vector<FrameDraw> draws;
    std::size_t opaque_draws = 0;
    std::vector<FramePoint> points;       // fully dynamic frames: one point, static_draw 0
    bool depth_test = true;               // AssemblerOptions::opaque_pass
    std::int64_t depth_denominator = 0;   // as SceneMeshes::depth_denominator
    FrameStats stats;
};

struct AssemblerOptions {
    // The opaque pass (opaque polygons with depth writes). Off: every
    // sprite draws its boundary polygons blended, in painter's order
    // batches, and the frame needs no depth buffer.
    bool opaque_pass = true;
    // The sampling filter the analyses were made for (as Scene::filter):
    // with nearest, a sprite whose opaque polygons cover all its
    // non-transparent texels needs no blend draw.
    Filter filter = Filter::nearest;
    // The broad phase of the per-frame overlap test: a grid of cells of
    // this many screen pixels over the frame's bounds (sprites outside
    // count in the border cells). A sprite whose box covers more than
    // cell_budget cells is treated as overlapping everything: work per
    // sprite stays bounded, so a frame is linear in its sprites.
    double cell_size = 64;
    int cell_budget = 64;
    int max_cells = 1 << 16; // larger bounds get larger cells
};

class FrameAssembler {
public:
    FrameAssembler() : options_() {}
    explicit FrameAssembler(const AssemblerOptions& options) : options_(options) {}

    // Analysed once: the picture's boundary polygons (triangulated, with
    // their texel skirts) and opaque polygons become templates that every
    // sprite showing it transforms. `id` gets the picture's id.
    FrameStatus add_image(const SpriteImage& image, int* id);
    // An animation: the pictures it shows in turn (ids of add_image).
    FrameStatus add_animation(std::span<const int> images, int* id);

    // Grows every buffer (the assembler's and `out`'s) for frames of up to
    // `sprites` sprites, so that such frames allocate nothing. More than
    // kMaxDepthLevels (one level per sprite: no frame holds more) is
    // too_many_sprites, and nothing is reserved.
    FrameStatus reserve(std::size_t sprites, AssembledFrame* out);

    // A fully dynamic frame: sprites in painter's order (sprites[0] farthest
    // back), bounds the part of the world the overlap grid covers (the
    // camera's view). Sprite i gets depth level i.
    FrameStatus assemble(std::span<const Sprite> sprites, const Viewport& bounds, AssembledFrame* out);

    // Sprites at the insertion points of static meshes (reconstructed with
    // ReconstructOptions::insertion_points): sprites[k] (painter's order)
    // are drawn at point k, at most its reserved levels each. The frame's
    // opaque draws go before the static ones; point k's blend draws between
    // the static blend draws (FramePoint). runtime::Renderer::draw_frame
    // draws it all.
    FrameStatus assemble_at(const SceneMeshes& static_meshes, std::span<const std::span<const Sprite>> sprites,
                            const Viewport& bounds, AssembledFrame* out);

    std::size_t image_count() const { return images_.size(); }

    // Why the latest call that did not return ok was refused (left as it
    // was by calls that succeed).
    const FrameProblem& problem() const { return problem_; }

private:
    struct Template {
        std::vector<double> xy;   // texel positions relative to the rect's top-left
        std::vector<float> uv;    // texture coordinates 0..1
        std::vector<std::uint32_t> indices;
        // The same vertices for emit_groups (SSE2): per vertex {x, x, y, y}
        // (a transform row multiplies them whole); per group of 4 vertices
        // the texture coordinates in the lanes of the group's 9 float
        // vectors 0, 1, 3, 5 and 7 (zero elsewhere): 20 floats.
        std::vector<double> xxyy;
        std::vector<float> uv_lanes;
        std::int32_t opaque_key = 0; // the opaque pass's key of its picture (texture * 4 + blend)
        std::uint32_t vertex_count = 0, index_count = 0; // xy.size() / 2; the indices used (3 more are held)
    };
    static constexpr std::uint32_t kNone = 0xffffffffu;
    // Templates per texel margin: kTexelMargin * 2^b for bucket b. A sprite
    // scaled below 1/8 needs a wider margin (texel_margin.cpp) and takes the
    // bucket of the next power of two up to half a texel.
    static constexpr int kMarginBuckets = 5;
    struct Picture { // template ids index templates_ (add_image sets absent ones to kNone)
        int texture = 0;
        Rect rect;
        std::uint32_t plain = kNone;                     // boundary polygons, for transforms that snap exactly
        std::uint32_t boundary[kMarginBuckets] = {};     // boundary polygons with their texel skirt
        std::uint32_t opaque[kMarginBuckets] = {}, quad = kNone;
        bool boundary_inside = false; // analysis boundary within the rect
        bool has_boundary = false, has_opaque = false;
        bool opaque_covers_all = false;
        bool bleeding_edges = false; // ImageAnalysis::bleeding_edges: turned or scaled, it draws its rect
        double bx0 = 0, by0 = 0, bx1 = 0, by1 = 0; // what it draws, texels relative to the rect
    };
    // Per sprite, this frame: what the index pass needs (16 bytes: the
    // frame reads and writes it once per sprite).
    struct Plan {
        std::uint32_t base;          // the sprite's first vertex (opaque template, then blend template)
        std::int32_t batch;          // its blend batch
        std::uint32_t opaque_template, blend_template; // ids, or kNone
    };
    struct SpriteShape; // plan_sprite's answer

    FrameStatus plan_sprite(const Sprite& s, SpriteShape& p) const;
    FrameProblem sprite_problem(const Sprite& s) const; // the slow path of a refused sprite
    FrameStatus refuse(FrameStatus status, const char* field, const char* reason, std::int64_t item = -1,
                       std::optional<double> value = std::nullopt);
    FrameStatus run(const Viewport& bounds, AssembledFrame* out);

    AssemblerOptions options_;
    FrameProblem problem_;
    std::vector<Template> templates_;
    std::vector<Picture> images_;
    std::vector<std::vector<int>> animations_;
    int max_texture_ = -1;
    std::size_t max_vertices_ = 0, max_indices_ = 0; // of one sprite

    // Per-frame scratch, kept at capacity.
    std::vector<Plan> plan_;
    struct Range { // a point's sprites this frame: plan_[first, end), levels from first_level
        std::uint32_t static_draw = 0, first = 0, end = 0;
        const Sprite* sprites = nullptr;
        std::int64_t first_level = 0;
    };
    std::vector<Range> ranges_;
    std::vector<std::int32_t> cell_top_;
    std::vector<std::int32_t> batch_key_, last_batch_of_key_, batch_count_;
    std::vector<std::uint32_t> point_batch_; // per point: its first batch; then the batch count
    std::vector<std::int32_t> key_count_;
    std::vector<std::int64_t> key_nearest_;
    std::vector<std::int32_t> key_order_;
    std::int64_t denominator_ = 0;
};

} // namespace depthcull
