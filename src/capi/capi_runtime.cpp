// depthcull.h: the runtime renderer (depthcull::runtime) in the host's GL
// context. A build without it (DEPTHCULL_BUILD_RUNTIME=OFF) keeps the
// functions, answering DC_ERROR_UNSUPPORTED, so callers link either way.
#include "capi/capi_internal.h"

using namespace depthcull;
using depthcull::capi::fail;
using depthcull::capi::guard;

#ifdef DEPTHCULL_C_HAVE_RUNTIME

#include "depthcull/runtime.h"

struct dc_renderer {
    std::unique_ptr<runtime::Renderer> renderer;
};

namespace {

// runtime::Renderer::create takes a plain function; the C loader reaches
// it through this thread's slot, set only for the duration of create.
thread_local dc_gl_loader current_loader = nullptr;
void* call_current_loader(const char* name) { return reinterpret_cast<void*>(current_loader(name)); }

dc_status runtime_status(const char* function, runtime::Status status, const runtime::Renderer& r) {
    switch (status) {
    case runtime::Status::ok: return DC_OK;
    case runtime::Status::bad_image:
    case runtime::Status::bad_meshes: return fail(DC_ERROR_INVALID_ARGUMENT, function, r.error().c_str());
    case runtime::Status::no_gl:
    case runtime::Status::shader_failed:
    case runtime::Status::gl_error: return fail(DC_ERROR_GL, function, r.error().c_str());
    }
    return fail(DC_ERROR_INTERNAL, function, "unknown runtime status");
}

} // namespace

extern "C" {

dc_status dc_renderer_create(dc_gl_loader loader, dc_renderer** out) {
    return guard("dc_renderer_create", [&] {
        if (!loader || !out) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_renderer_create: loader and out must not be NULL");
        std::string error;
        current_loader = loader;
        auto r = runtime::Renderer::create(&call_current_loader, &error);
        current_loader = nullptr;
        if (!r) return fail(DC_ERROR_GL, "dc_renderer_create", error.c_str());
        *out = new dc_renderer{std::move(r)};
        return DC_OK;
    });
}

void dc_renderer_destroy(dc_renderer* renderer) { delete renderer; }

const char* dc_renderer_gl_version(const dc_renderer* renderer) { return renderer ? renderer->renderer->gl_version().c_str() : ""; }

dc_status dc_renderer_upload_images(dc_renderer* renderer, const dc_image_pixels* images, size_t count, dc_filter filter) {
    return guard("dc_renderer_upload_images", [&] {
        if (!renderer || (count && !images)) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_renderer_upload_images: renderer and images must not be NULL");
        if (filter != DC_FILTER_NEAREST && filter != DC_FILTER_LINEAR) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_renderer_upload_images: unknown filter");
        std::vector<ImageView> views(count);
        for (std::size_t i = 0; i < count; ++i) {
            const dc_image_pixels& p = images[i];
            if (!p.rgba || p.width <= 0 || p.height <= 0 || p.stride < ptrdiff_t(p.width) * 4)
                return fail(DC_ERROR_INVALID_ARGUMENT, "dc_renderer_upload_images: image " + std::to_string(i) + " has no pixels, no size or a stride below 4 * width");
            views[i] = ImageView{p.rgba, p.width, p.height, p.stride};
        }
        return runtime_status("dc_renderer_upload_images",
                              renderer->renderer->upload_images(views, filter == DC_FILTER_LINEAR ? Filter::linear : Filter::nearest), *renderer->renderer);
    });
}

dc_status dc_renderer_set_textures(dc_renderer* renderer, const unsigned* gl_texture_names, size_t count) {
    return guard("dc_renderer_set_textures", [&] {
        if (!renderer || (count && !gl_texture_names)) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_renderer_set_textures: renderer and names must not be NULL");
        return runtime_status("dc_renderer_set_textures", renderer->renderer->set_textures({gl_texture_names, count}), *renderer->renderer);
    });
}

dc_status dc_renderer_set_meshes(dc_renderer* renderer, const dc_meshes* meshes) {
    return guard("dc_renderer_set_meshes", [&] {
        if (!renderer || !meshes) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_renderer_set_meshes: renderer and meshes must not be NULL");
        return runtime_status("dc_renderer_set_meshes", renderer->renderer->set_meshes(meshes->document.meshes), *renderer->renderer);
    });
}

dc_status dc_renderer_reserve_dynamic(dc_renderer* renderer, size_t vertices, size_t indices) {
    return guard("dc_renderer_reserve_dynamic", [&] {
        if (!renderer) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_renderer_reserve_dynamic: renderer must not be NULL");
        return runtime_status("dc_renderer_reserve_dynamic", renderer->renderer->reserve_dynamic(vertices, indices), *renderer->renderer);
    });
}

dc_status dc_renderer_draw(dc_renderer* renderer, const dc_camera* camera, const dc_meshes* dynamic, const dc_frame_options* options,
                           dc_frame_counts* counts) {
    return guard("dc_renderer_draw", [&] {
        if (!renderer || !camera) return fail(DC_ERROR_INVALID_ARGUMENT, "dc_renderer_draw: renderer and camera must not be NULL");
        const runtime::Camera c{camera->x, camera->y, camera->width, camera->height, camera->flip_y != 0};
        runtime::FrameOptions o;
        if (options) {
            o.clear_color = options->clear_color != 0;
            o.count_samples = options->count_samples != 0;
        }
        runtime::FrameCounts n;
        std::span<const Draw> draws;
        if (dynamic) draws = dynamic->document.meshes.draws;
        if (dc_status s = runtime_status("dc_renderer_draw", renderer->renderer->draw(c, draws, o, &n), *renderer->renderer)) return s;
        if (counts) *counts = dc_frame_counts{n.draw_calls, n.triangles, n.samples_passed};
        return DC_OK;
    });
}

dc_status dc_renderer_draw_frame(dc_renderer* renderer, const dc_camera* camera, const dc_frame* frame, const dc_frame_options* options,
                                 dc_frame_counts* counts) {
    return guard("dc_renderer_draw_frame", [&] {
        if (!renderer || !camera || !frame)
            return fail(DC_ERROR_INVALID_ARGUMENT, "dc_renderer_draw_frame: renderer, camera and frame must not be NULL");
        const runtime::Camera c{camera->x, camera->y, camera->width, camera->height, camera->flip_y != 0};
        runtime::FrameOptions o;
        if (options) {
            o.clear_color = options->clear_color != 0;
            o.count_samples = options->count_samples != 0;
        }
        runtime::FrameCounts n;
        if (dc_status s = runtime_status("dc_renderer_draw_frame", renderer->renderer->draw_frame(c, frame->frame, o, &n), *renderer->renderer))
            return s;
        if (counts) *counts = dc_frame_counts{n.draw_calls, n.triangles, n.samples_passed};
        return DC_OK;
    });
}

} // extern "C"

#else // no runtime in this build

struct dc_renderer {};

namespace {
dc_status unsupported(const char* function) {
    return fail(DC_ERROR_UNSUPPORTED, function, "this build has no runtime renderer (DEPTHCULL_BUILD_RUNTIME=OFF)");
}
} // namespace

extern "C" {
dc_status dc_renderer_create(dc_gl_loader, dc_renderer**) { return unsupported("dc_renderer_create"); }
void dc_renderer_destroy(dc_renderer*) {}
const char* dc_renderer_gl_version(const dc_renderer*) { return ""; }
dc_status dc_renderer_upload_images(dc_renderer*, const dc_image_pixels*, size_t, dc_filter) { return unsupported("dc_renderer_upload_images"); }
dc_status dc_renderer_set_textures(dc_renderer*, const unsigned*, size_t) { return unsupported("dc_renderer_set_textures"); }
dc_status dc_renderer_set_meshes(dc_renderer*, const dc_meshes*) { return unsupported("dc_renderer_set_meshes"); }
dc_status dc_renderer_reserve_dynamic(dc_renderer*, size_t, size_t) { return unsupported("dc_renderer_reserve_dynamic"); }
dc_status dc_renderer_draw(dc_renderer*, const dc_camera*, const dc_meshes*, const dc_frame_options*, dc_frame_counts*) {
    return unsupported("dc_renderer_draw");
}
dc_status dc_renderer_draw_frame(dc_renderer*, const dc_camera*, const dc_frame*, const dc_frame_options*, dc_frame_counts*) {
    return unsupported("dc_renderer_draw_frame");
}
} // extern "C"

#endif
