// depthcull.h: moving sprites (depthcull/frame.h) through the C API. Pure:
// no GL; dc_renderer_draw_frame (capi_runtime.cpp) draws the frames.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

#include "capi/capi_internal.h"

using namespace depthcull;
using depthcull::capi::fail;
using depthcull::capi::guard;

namespace {

// A value as a message shows it: whole numbers (ids, counts) in full,
// others as %g (1e+300).
std::string value_text(double v) {
    if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9007199254740992.0) return std::to_string(std::int64_t(v));
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

// The assembler's FrameProblem as a message: "sprite 3: transform[4]
// 1e+300 is not a finite number within +-1e9 (kMaxCoordinate)". `item`
// names what FrameProblem::item counts ("sprite", "frame").
std::string problem_text(const FrameProblem& p, const char* item) {
    std::string text;
    if (p.point >= 0) text += "point " + std::to_string(p.point) + (p.item >= 0 ? ", " : ": ");
    if (p.item >= 0) text += std::string(item) + " " + std::to_string(p.item) + ": ";
    text += p.field;
    if (p.component >= 0) text += "[" + std::to_string(p.component) + "]";
    if (p.has_value) text += " " + value_text(p.value);
    return text + " " + p.reason;
}

std::string rect_text(const Rect& r) {
    return std::to_string(r.x) + ", " + std::to_string(r.y) + ", " + std::to_string(r.w) + "x" + std::to_string(r.h);
}

dc_status frame_status(const char* function, FrameStatus status, const FrameAssembler& assembler, const char* item = "sprite") {
    const std::string problem = std::string(function) + ": " + problem_text(assembler.problem(), item);
    switch (status) {
    case FrameStatus::ok: return DC_OK;
    case FrameStatus::bad_image:
    case FrameStatus::bad_sprite:
    case FrameStatus::bad_meshes: return fail(DC_ERROR_INVALID_ARGUMENT, problem);
    case FrameStatus::too_many_sprites: return fail(DC_ERROR_TOO_MANY_DEPTH_LEVELS, problem);
    }
    return fail(DC_ERROR_INTERNAL, function, "unknown frame status");
}

// A C sprite as the assembler's; false for a blend that is no dc_blend.
bool convert(const dc_sprite& c, Sprite& s) {
    s.image = c.image > uint32_t(INT32_MAX) ? -1 : int(c.image);
    s.animation = c.animation;
    s.frame = c.frame;
    std::copy(c.transform, c.transform + 6, s.transform.begin());
    std::copy(c.color, c.color + 4, s.color.begin());
    if (c.blend < 0 || c.blend > 3) return false;
    s.blend = Blend(c.blend);
    return true;
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
        const Rect r{rect.x, rect.y, rect.w, rect.h};
        const SpriteImage image{int(texture), texture_width, texture_height, r, analysis->analysis.get()};
        const FrameStatus status = assembler->assembler.add_image(image, &picture);
        if (const Rect& of = analysis->analysis->rect; status == FrameStatus::bad_image && !(of == r) &&
                                                       std::string_view(assembler->assembler.problem().field) == "analysis")
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assembler_add_image: the analysis is of another rect (" + rect_text(of) + ") than the picture's (" +
                                                       rect_text(r) + ")");
        if (dc_status s = frame_status("dc_assembler_add_image", status, assembler->assembler)) return s;
        *id = uint32_t(picture);
        return DC_OK;
    });
}

dc_status dc_assembler_add_animation(dc_assembler* assembler, const uint32_t* images, size_t count, uint32_t* id) {
    return guard("dc_assembler_add_animation", [&] {
        if (!assembler || !images || !id) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assembler_add_animation: arguments must not be NULL");
        if (count == 0) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assembler_add_animation: count is 0: an animation shows at least one picture");
        const std::size_t pictures = assembler->assembler.image_count();
        for (size_t i = 0; i < count; ++i)
            if (images[i] >= pictures) // before the copy: a bad count is no reason to allocate
                return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assembler_add_animation: frame " + std::to_string(i) + ": image " + std::to_string(images[i]) +
                                                           " is not a dc_assembler_add_image id (the assembler has " + std::to_string(pictures) + ")");
        std::vector<int> frames(images, images + count);
        int animation = -1;
        if (dc_status s = frame_status("dc_assembler_add_animation", assembler->assembler.add_animation(frames, &animation), assembler->assembler, "frame"))
            return s;
        *id = uint32_t(animation);
        return DC_OK;
    });
}

dc_status dc_assembler_reserve(dc_assembler* assembler, size_t sprites, dc_frame* frame) {
    return guard("dc_assembler_reserve", [&] {
        if (!assembler || !frame) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assembler_reserve: assembler and frame must not be NULL");
        // Checked before anything is allocated (the assembler checks too).
        if (sprites > std::size_t(kMaxDepthLevels))
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assembler_reserve: " + std::to_string(sprites) + " sprites are more than a frame holds (" +
                                                       std::to_string(kMaxDepthLevels) + ", one depth level each: kMaxDepthLevels)");
        if (dc_status s = frame_status("dc_assembler_reserve", assembler->assembler.reserve(sprites, &frame->frame), assembler->assembler)) return s;
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
        for (size_t i = 0; i < count; ++i)
            if (!convert(sprites[i], frame->sprites[i]))
                return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assemble: a sprite's blend is not a dc_blend");
        return frame_status("dc_assemble",
                            assembler->assembler.assemble(frame->sprites, Viewport{bounds.x, bounds.y, bounds.width, bounds.height}, &frame->frame),
                            assembler->assembler);
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

dc_status dc_scene_add_insertion_point(dc_scene* scene, int64_t levels) {
    return guard("dc_scene_add_insertion_point", [&] {
        if (!scene) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_scene_add_insertion_point: scene must not be NULL");
        if (levels < 0 || levels > kMaxDepthLevels)
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_scene_add_insertion_point: levels must be 0.." + std::to_string(kMaxDepthLevels));
        InsertionPoint point;
        point.element = scene->scene.elements.size();
        point.levels = levels;
        scene->points.push_back(point);
        scene->scene.insertion_points.push_back(point.element);
        return DC_OK;
    });
}

size_t dc_meshes_insertion_point_count(const dc_meshes* meshes) { return meshes ? meshes->document.meshes.insertion_points.size() : 0; }

dc_status dc_meshes_insertion_point(const dc_meshes* meshes, size_t i, dc_insertion_point* out) {
    if (!meshes || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_insertion_point: meshes and out must not be NULL");
    const auto& points = meshes->document.meshes.insertion_points;
    if (i >= points.size()) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_insertion_point: index out of range");
    const InsertionPoint& p = points[i];
    *out = dc_insertion_point{p.element, p.levels, p.first_level, p.blend_draw};
    return DC_OK;
}

dc_status dc_assemble_at(dc_assembler* assembler, const dc_meshes* static_meshes, const dc_sprite* const* sprites, const size_t* counts,
                         size_t points, dc_viewport bounds, dc_frame* frame) {
    return guard("dc_assemble_at", [&] {
        if (!assembler || !static_meshes || !frame || (points && (!sprites || !counts)))
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assemble_at: arguments must not be NULL");
        if (points > static_meshes->document.meshes.insertion_points.size())
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assemble_at: more sprite lists than the meshes' insertion points");
        std::size_t total = 0;
        for (size_t k = 0; k < points; ++k) {
            if (counts[k] && !sprites[k]) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assemble_at: a sprite list must not be NULL");
            if (std::int64_t(counts[k]) > static_meshes->document.meshes.insertion_points[k].levels || counts[k] > std::size_t(kMaxDepthLevels))
                return fail(DC_ERROR_TOO_MANY_DEPTH_LEVELS, "dc_assemble_at: point " + std::to_string(k) + ": " + std::to_string(counts[k]) +
                                                                " sprites are more than the point's reserved levels (" +
                                                                std::to_string(static_meshes->document.meshes.insertion_points[k].levels) + ")");
            total += counts[k];
        }
        // One array for all points (kept at capacity), then the spans.
        frame->sprites.resize(total);
        frame->lists.clear();
        std::size_t at = 0;
        for (size_t k = 0; k < points; ++k) {
            for (size_t i = 0; i < counts[k]; ++i)
                if (!convert(sprites[k][i], frame->sprites[at + i]))
                    return fail(DC_ERROR_INVALID_ARGUMENT, "dc_assemble_at: a sprite's blend is not a dc_blend");
            frame->lists.emplace_back(frame->sprites.data() + at, counts[k]);
            at += counts[k];
        }
        return frame_status("dc_assemble_at",
                            assembler->assembler.assemble_at(static_meshes->document.meshes, frame->lists,
                                                             Viewport{bounds.x, bounds.y, bounds.width, bounds.height}, &frame->frame),
                            assembler->assembler);
    });
}

size_t dc_frame_draw_count(const dc_frame* frame) { return frame ? frame->frame.draws.size() : 0; }

dc_status dc_frame_draw_get(const dc_frame* frame, size_t i, dc_frame_draw* out) {
    if (!frame || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_frame_draw_get: frame and out must not be NULL");
    if (i >= frame->frame.draws.size()) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_frame_draw_get: index out of range");
    const FrameDraw& d = frame->frame.draws[i];
    *out = dc_frame_draw{uint32_t(d.image), d.pass == Pass::opaque ? DC_PASS_OPAQUE : DC_PASS_BLEND, int(d.blend), d.first_index, d.index_count};
    return DC_OK;
}

size_t dc_frame_point_count(const dc_frame* frame) { return frame ? frame->frame.points.size() : 0; }

dc_status dc_frame_point_get(const dc_frame* frame, size_t i, dc_frame_point* out) {
    if (!frame || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_frame_point_get: frame and out must not be NULL");
    if (i >= frame->frame.points.size()) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_frame_point_get: index out of range");
    const FramePoint& p = frame->frame.points[i];
    *out = dc_frame_point{p.static_draw, p.first_draw, p.end_draw};
    return DC_OK;
}

} // extern "C"
