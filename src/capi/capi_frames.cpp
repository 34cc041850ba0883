// depthcull.h: moving sprites (depthcull/frame.h) through the C API. Pure:
// no GL; dc_renderer_draw_frame (capi_runtime.cpp) draws the frames.
#include <algorithm>

#include "capi/capi_internal.h"

using namespace depthcull;
using depthcull::capi::fail;
using depthcull::capi::guard;

namespace {

dc_status frame_status(const char* function, FrameStatus status) {
    switch (status) {
    case FrameStatus::ok: return DC_OK;
    case FrameStatus::bad_image: return fail(DC_ERROR_INVALID_ARGUMENT, function, "bad picture: empty rect, rect outside its texture, or no analysis");
    case FrameStatus::bad_sprite: return fail(DC_ERROR_INVALID_ARGUMENT, function, "a sprite names an unknown picture or animation, or has a non-finite transform or colour");
    case FrameStatus::too_many_sprites: return fail(DC_ERROR_TOO_MANY_DEPTH_LEVELS, function, "more sprites than depth levels");
    case FrameStatus::bad_meshes: return fail(DC_ERROR_INVALID_ARGUMENT, function, "static meshes without the insertion points asked for");
    }
    return fail(DC_ERROR_INTERNAL, function, "unknown frame status");
}

} // namespace

extern "C" {

void dc_sprite_default(dc_sprite* sprite) {
    if (!sprite) return;
    *sprite = dc_sprite{};
    sprite->animation = -1;
    const double identity[6] = {1, 0, 0, 1, 0, 0};
    std::copy(identity, identity + 6, sprite->transform);
    std::fill(sprite->color, sprite->color + 4, 1.0f);
    sprite->blend = DC_BLEND_ALPHA;
}

dc_status dc_assembler_create(dc_assembler** out) {
    return guard("dc_assembler_create", [&] {
        if (!out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assembler_create: out must not be NULL");
        *out = new dc_assembler{};
        return DC_OK;
    });
}

void dc_assembler_destroy(dc_assembler* assembler) { delete assembler; }

dc_status dc_assembler_add_image(dc_assembler* assembler, uint32_t texture, int texture_width, int texture_height, dc_rect rect,
                                 const dc_analysis* analysis, uint32_t* id) {
    return guard("dc_assembler_add_image", [&] {
        if (!assembler || !analysis || !id || texture > uint32_t(INT32_MAX))
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assembler_add_image: assembler, analysis and id must not be NULL");
        int picture = -1;
        const SpriteImage image{int(texture), texture_width, texture_height, Rect{rect.x, rect.y, rect.w, rect.h}, analysis->analysis.get()};
        if (dc_status s = frame_status("dc_assembler_add_image", assembler->assembler.add_image(image, &picture))) return s;
        *id = uint32_t(picture);
        return DC_OK;
    });
}

dc_status dc_assembler_add_animation(dc_assembler* assembler, const uint32_t* images, size_t count, uint32_t* id) {
    return guard("dc_assembler_add_animation", [&] {
        if (!assembler || !images || !id) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assembler_add_animation: arguments must not be NULL");
        std::vector<int> frames;
        for (size_t i = 0; i < count; ++i) frames.push_back(images[i] > uint32_t(INT32_MAX) ? -1 : int(images[i]));
        int animation = -1;
        if (dc_status s = frame_status("dc_assembler_add_animation", assembler->assembler.add_animation(frames, &animation))) return s;
        *id = uint32_t(animation);
        return DC_OK;
    });
}

dc_status dc_assembler_reserve(dc_assembler* assembler, size_t sprites, dc_frame* frame) {
    return guard("dc_assembler_reserve", [&] {
        if (!assembler || !frame) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assembler_reserve: assembler and frame must not be NULL");
        assembler->assembler.reserve(sprites, &frame->frame);
        frame->sprites.reserve(sprites);
        return DC_OK;
    });
}

dc_status dc_frame_create(dc_frame** out) {
    return guard("dc_frame_create", [&] {
        if (!out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_frame_create: out must not be NULL");
        *out = new dc_frame{};
        return DC_OK;
    });
}

void dc_frame_destroy(dc_frame* frame) { delete frame; }

dc_status dc_assemble(dc_assembler* assembler, const dc_sprite* sprites, size_t count, dc_viewport bounds, dc_frame* frame) {
    return guard("dc_assemble", [&] {
        if (!assembler || !frame || (count && !sprites)) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assemble: arguments must not be NULL");
        frame->sprites.resize(count);
        for (size_t i = 0; i < count; ++i) {
            const dc_sprite& c = sprites[i];
            Sprite& s = frame->sprites[i];
            s.image = c.image > uint32_t(INT32_MAX) ? -1 : int(c.image);
            s.animation = c.animation;
            s.frame = c.frame;
            std::copy(c.transform, c.transform + 6, s.transform.begin());
            std::copy(c.color, c.color + 4, s.color.begin());
            if (c.blend < 0 || c.blend > 3) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assemble: a sprite's blend is not a dc_blend");
            s.blend = Blend(c.blend);
        }
        return frame_status("dc_assemble", assembler->assembler.assemble(frame->sprites, Viewport{bounds.x, bounds.y, bounds.width, bounds.height},
                                                                         &frame->frame));
    });
}

dc_status dc_frame_stats_get(const dc_frame* frame, dc_frame_stats* out) {
    if (!frame || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_frame_stats_get: frame and out must not be NULL");
    const FrameStats& s = frame->frame.stats;
    *out = dc_frame_stats{s.sprites, s.draw_calls, s.opaque_draws, s.triangles, s.blend_batches, s.over_budget};
    return DC_OK;
}

const float* dc_frame_vertices(const dc_frame* frame, size_t* vertex_count) {
    if (!frame) return nullptr;
    if (vertex_count) *vertex_count = frame->frame.vertices.size() / kVertexFloats;
    return frame->frame.vertices.data();
}

const uint32_t* dc_frame_indices(const dc_frame* frame, size_t* index_count) {
    if (!frame) return nullptr;
    if (index_count) *index_count = frame->frame.indices.size();
    return frame->frame.indices.data();
}

} // extern "C"
