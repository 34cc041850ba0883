// depthcull.h: meshes, their draws and the mesh files (docs/mesh-format.md).
#include <cstdlib>
#include <cstring>

#include "capi/capi_internal.h"

using namespace depthcull;
using depthcull::capi::fail;
using depthcull::capi::guard;

namespace {

std::string to_bytes(const dc_meshes& m, dc_format format, unsigned flags, const std::string& output_path) {
    const bool timing = !(flags & DC_WRITE_NO_TIMING);
    // With the animations, so a file read and written keeps them.
    return format == DC_FORMAT_BINARY ? io::meshes_to_binary(m.loaded, output_path, timing) : io::meshes_to_json(m.loaded, output_path, timing);
}

} // namespace

extern "C" {

dc_status dc_meshes_create(dc_meshes** out) {
    return guard("dc_meshes_create", [&] {
        if (!out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_create: out must not be NULL");
        *out = new dc_meshes();
        return DC_OK;
    });
}

void dc_meshes_destroy(dc_meshes* meshes) { delete meshes; }

dc_status dc_meshes_info_get(const dc_meshes* meshes, dc_meshes_info* out) {
    if (!meshes || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_info_get: meshes and out must not be NULL");
    const SceneMeshes& m = meshes->loaded.meshes;
    const SceneStats& s = m.stats;
    *out = dc_meshes_info{{m.viewport.x, m.viewport.y, m.viewport.width, m.viewport.height},
                          m.depth_test,
                          {s.elements, s.draw_calls, s.triangles, s.depth_levels, s.graph_edges, s.depth_bits, meshes->loaded.seconds}};
    return DC_OK;
}

size_t dc_meshes_draw_count(const dc_meshes* meshes) { return meshes ? meshes->loaded.meshes.draws.size() : 0; }

dc_status dc_meshes_draw(const dc_meshes* meshes, size_t i, dc_draw* out) {
    if (!meshes || !out || i >= meshes->loaded.meshes.draws.size())
        return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_draw: NULL argument or draw index out of range");
    const Draw& d = meshes->loaded.meshes.draws[i];
    *out = dc_draw{uint32_t(d.image), d.pass == Pass::opaque ? DC_PASS_OPAQUE : DC_PASS_BLEND, int(d.blend),
                   d.vertices.data(), d.vertex_count(), d.indices.data(), d.indices.size()};
    return DC_OK;
}

size_t dc_meshes_image_count(const dc_meshes* meshes) { return meshes ? meshes->loaded.images.size() : 0; }

dc_status dc_meshes_image(const dc_meshes* meshes, size_t i, dc_image_info* out) {
    if (!meshes || !out || i >= meshes->loaded.images.size())
        return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_image: NULL argument or image index out of range");
    const SceneImage& img = meshes->loaded.images[i];
    *out = dc_image_info{img.id.c_str(), img.path.c_str(), img.width, img.height, img.has_trans ? 1 : 0, img.trans};
    return DC_OK;
}

size_t dc_meshes_animation_count(const dc_meshes* meshes) { return meshes ? meshes->loaded.animations.size() : 0; }

size_t dc_meshes_animation_frame_count(const dc_meshes* meshes, size_t animation) {
    return meshes && animation < meshes->loaded.animations.size() ? meshes->loaded.animations[animation].frames.size() : 0;
}

dc_status dc_meshes_animation_frame(const dc_meshes* meshes, size_t animation, size_t frame, dc_animation_frame* out) {
    if (!meshes || !out || animation >= meshes->loaded.animations.size() || frame >= meshes->loaded.animations[animation].frames.size())
        return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_animation_frame: NULL argument or animation or frame index out of range");
    const AnimationFrame& f = meshes->loaded.animations[animation].frames[frame];
    *out = dc_animation_frame{std::uint32_t(f.image), dc_rect{f.rect.x, f.rect.y, f.rect.w, f.rect.h}, f.duration_ms};
    return DC_OK;
}

size_t dc_meshes_animated_run_count(const dc_meshes* meshes) { return meshes ? meshes->loaded.animated.size() : 0; }

dc_status dc_meshes_animated_run(const dc_meshes* meshes, size_t i, dc_animated_run* out) {
    if (!meshes || !out || i >= meshes->loaded.animated.size())
        return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_animated_run: NULL argument or run index out of range");
    const io::AnimatedRun& r = meshes->loaded.animated[i];
    *out = dc_animated_run{r.draw, r.first_vertex, r.vertex_count, r.animation};
    return DC_OK;
}

dc_status dc_meshes_read_file(const char* path, dc_meshes** out) {
    return guard("dc_meshes_read_file", [&] {
        if (!path || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_read_file: path and out must not be NULL");
        auto meshes = std::make_unique<dc_meshes>();
        meshes->loaded = io::read_meshes(path);
        *out = meshes.release();
        return DC_OK;
    });
}

dc_status dc_meshes_read_memory(const void* data, size_t size, const char* base_dir, dc_meshes** out) {
    return guard("dc_meshes_read_memory", [&] {
        if ((!data && size) || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_read_memory: data and out must not be NULL");
        const std::string_view bytes(static_cast<const char*>(data), size);
        const std::string base = base_dir ? base_dir : "";
        auto meshes = std::make_unique<dc_meshes>();
        meshes->loaded = io::is_binary_meshes(bytes) ? io::meshes_from_binary(bytes, "memory", base) : io::meshes_from_json(bytes, "memory", base);
        *out = meshes.release();
        return DC_OK;
    });
}

dc_status dc_meshes_write_file(const dc_meshes* meshes, const char* path, dc_format format, unsigned flags) {
    return guard("dc_meshes_write_file", [&] {
        if (!meshes || !path) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_write_file: meshes and path must not be NULL");
        if (format != DC_FORMAT_JSON && format != DC_FORMAT_BINARY) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_write_file: unknown format");
        // Streamed into the file: a large scene's meshes are never one string.
        const bool timing = !(flags & DC_WRITE_NO_TIMING);
        io::write_file_atomic(path, [&](const io::WriteBytes& write) {
            format == DC_FORMAT_BINARY ? io::stream_meshes_binary(write, meshes->loaded, path, timing)
                                       : io::stream_meshes_json(write, meshes->loaded, path, timing);
        });
        return DC_OK;
    });
}

dc_status dc_meshes_write_memory(const dc_meshes* meshes, dc_format format, unsigned flags, void** data, size_t* size) {
    return guard("dc_meshes_write_memory", [&] {
        if (!meshes || !data || !size) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_write_memory: meshes, data and size must not be NULL");
        if (format != DC_FORMAT_JSON && format != DC_FORMAT_BINARY) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_write_memory: unknown format");
        const std::string bytes = to_bytes(*meshes, format, flags, "");
        void* copy = std::malloc(bytes.size() ? bytes.size() : 1);
        if (!copy) throw std::bad_alloc();
        std::memcpy(copy, bytes.data(), bytes.size());
        *data = copy;
        *size = bytes.size();
        return DC_OK;
    });
}

void dc_free(void* data) { std::free(data); }

} // extern "C"
