// depthcull.h: meshes, their draws and the mesh files (docs/mesh-format.md).
#include <cstdlib>
#include <cstring>
#include <string>
#include <string_view>

#include "capi/capi_internal.h"

using namespace depthcull;
using depthcull::capi::fail;
using depthcull::capi::guard;

namespace {

// The bytes of either form. DC_WRITE_NO_TIMING needs no handling: the
// handle's document says seconds 0 (capi_internal.h).
std::string to_bytes(const dc_meshes& m, dc_format format, const std::string& output_path) {
    // With the animations, so a file read and written keeps them.
    return format == DC_FORMAT_BINARY ? io::meshes_to_binary(m.document, output_path) : io::meshes_to_json(m.document, output_path);
}

// The handle of a document read from a file: its stats.seconds reported
// by dc_meshes_info_get, not written again.
std::unique_ptr<dc_meshes> read_handle(io::MeshesDocument document) {
    auto meshes = std::make_unique<dc_meshes>();
    meshes->seconds = document.seconds;
    document.seconds = 0;
    meshes->document = std::move(document);
    return meshes;
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
    const SceneMeshes& m = meshes->document.meshes;
    const SceneStats& s = m.stats;
    *out = dc_meshes_info{{m.viewport.x, m.viewport.y, m.viewport.width, m.viewport.height},
                          m.depth_test,
                          {s.elements, s.draw_calls, s.triangles, s.depth_levels, s.graph_edges, s.depth_bits, meshes->seconds}};
    return DC_OK;
}

size_t dc_meshes_draw_count(const dc_meshes* meshes) { return meshes ? meshes->document.meshes.draws.size() : 0; }

dc_status dc_meshes_draw(const dc_meshes* meshes, size_t i, dc_draw* out) {
    if (!meshes || !out || i >= meshes->document.meshes.draws.size())
        return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_draw: NULL argument or draw index out of range");
    const Draw& d = meshes->document.meshes.draws[i];
    *out = dc_draw{uint32_t(d.image), d.pass == Pass::opaque ? DC_PASS_OPAQUE : DC_PASS_BLEND, int(d.blend),
                   d.vertices.data(), d.vertex_count(), d.indices.data(), d.indices.size()};
    return DC_OK;
}

size_t dc_meshes_image_count(const dc_meshes* meshes) { return meshes ? meshes->document.images.size() : 0; }

dc_status dc_meshes_image(const dc_meshes* meshes, size_t i, dc_image_info* out) {
    if (!meshes || !out || i >= meshes->document.images.size())
        return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_image: NULL argument or image index out of range");
    const SceneImage& img = meshes->document.images[i];
    *out = dc_image_info{img.id.c_str(), img.path.c_str(), img.width, img.height, img.has_trans ? 1 : 0, img.trans};
    return DC_OK;
}

size_t dc_meshes_animation_count(const dc_meshes* meshes) { return meshes ? meshes->document.animations.size() : 0; }

size_t dc_meshes_animation_frame_count(const dc_meshes* meshes, size_t animation) {
    return meshes && animation < meshes->document.animations.size() ? meshes->document.animations[animation].frames.size() : 0;
}

dc_status dc_meshes_animation_frame(const dc_meshes* meshes, size_t animation, size_t frame, dc_animation_frame* out) {
    if (!meshes || !out || animation >= meshes->document.animations.size() || frame >= meshes->document.animations[animation].frames.size())
        return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_animation_frame: NULL argument or animation or frame index out of range");
    const AnimationFrame& f = meshes->document.animations[animation].frames[frame];
    *out = dc_animation_frame{std::uint32_t(f.image), dc_rect{f.rect.x, f.rect.y, f.rect.w, f.rect.h}, f.duration_ms};
    return DC_OK;
}

size_t dc_meshes_animated_run_count(const dc_meshes* meshes) { return meshes ? meshes->document.animated.size() : 0; }

dc_status dc_meshes_animated_run(const dc_meshes* meshes, size_t i, dc_animated_run* out) {
    if (!meshes || !out || i >= meshes->document.animated.size())
        return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_animated_run: NULL argument or run index out of range");
    const io::AnimatedRun& r = meshes->document.animated[i];
    *out = dc_animated_run{r.draw, r.first_vertex, r.vertex_count, r.animation};
    return DC_OK;
}

dc_status dc_meshes_read_file(const char* path, dc_meshes** out) {
    return guard("dc_meshes_read_file", [&] {
        if (!path || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_read_file: path and out must not be NULL");
        *out = read_handle(io::read_meshes(path)).release();
        return DC_OK;
    });
}

dc_status dc_meshes_read_memory(const void* data, size_t size, const char* base_dir, dc_meshes** out) {
    return guard("dc_meshes_read_memory", [&] {
        if ((!data && size) || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_read_memory: data and out must not be NULL");
        const std::string_view bytes(static_cast<const char*>(data), size);
        const std::string base = base_dir ? base_dir : "";
        *out = read_handle(io::is_binary_meshes(bytes) ? io::meshes_from_binary(bytes, "memory", base) : io::meshes_from_json(bytes, "memory", base))
                   .release();
        return DC_OK;
    });
}

dc_status dc_meshes_write_file(const dc_meshes* meshes, const char* path, dc_format format, unsigned flags) {
    return guard("dc_meshes_write_file", [&] {
        if (!meshes || !path) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_write_file: meshes and path must not be NULL");
        if (format != DC_FORMAT_JSON && format != DC_FORMAT_BINARY) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_write_file: unknown format");
        // The io writers take "" and "-" for standard output (the CLI's
        // meaning): from a library that would write into the host's stdout
        // and report a file written. A file named "-" is "./-".
        const std::string_view p(path);
        if (p.empty() || p == "-")
            return fail(DC_ERROR_INVALID_ARGUMENT, std::string("dc_meshes_write_file: path \"") + path +
                                                       "\" names no file (for a file named \"-\", pass \"./-\"; for bytes in memory, "
                                                       "dc_meshes_write_memory)");
        // Streamed into the file: a large scene's meshes are never one string.
        (void)flags; // DC_WRITE_NO_TIMING: what every write does now
        format == DC_FORMAT_BINARY ? io::write_meshes_binary(path, meshes->document) : io::write_meshes_json(path, meshes->document);
        return DC_OK;
    });
}

dc_status dc_meshes_write_memory(const dc_meshes* meshes, dc_format format, unsigned flags, void** data, size_t* size) {
    return guard("dc_meshes_write_memory", [&] {
        if (!meshes || !data || !size) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_write_memory: meshes, data and size must not be NULL");
        if (format != DC_FORMAT_JSON && format != DC_FORMAT_BINARY) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_meshes_write_memory: unknown format");
        (void)flags;
        const std::string bytes = to_bytes(*meshes, format, "");
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
