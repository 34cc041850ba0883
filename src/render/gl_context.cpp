// Headless OpenGL through EGL: no window, no X, no surface. On CPU-only
// machines Mesa's surfaceless platform gives llvmpipe; on a machine with a
// GPU the EGL device platform (eglQueryDevicesEXT) reaches the vendor's
// driver, so `automatic` tries hardware devices first.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstring>
#include <span>
#include <vector>

#include "render/gl.h"

namespace depthcull::render {

void GlContext::destroy() {
    if (display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
    // No eglTerminate: a platform's display is one per process, shared by
    // every renderer on it, and terminating it would end their contexts too.
    display = EGL_NO_DISPLAY;
    context = EGL_NO_CONTEXT;
}

namespace {

bool has_extension(const char* list, const char* name) {
    if (!list) return false;
    std::size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

std::string egl_error_text() {
    return "EGL error 0x" + [] {
        char buf[16];
        std::snprintf(buf, sizeof buf, "%04x", unsigned(eglGetError()));
        return std::string(buf);
    }();
}

// Initializes `display` and makes a desktop GL core context current on it:
// 4.5 first (what llvmpipe gives), then 3.3, the least our shaders need;
// with out->gles an OpenGL ES 3.0 context instead (to host the runtime
// renderer on the ES target).
std::string make_context(EGLDisplay display, const std::string& platform, GlContext* out) {
    if (display == EGL_NO_DISPLAY) return platform + ": no display";
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) return platform + ": eglInitialize failed (" + egl_error_text() + ")";
    auto fail = [&](const std::string& why) { return platform + ": " + why; };
    if (!eglBindAPI(out->gles ? EGL_OPENGL_ES_API : EGL_OPENGL_API)) return fail(out->gles ? "no OpenGL ES API" : "no desktop OpenGL API");
    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    if (!has_extension(extensions, "EGL_KHR_surfaceless_context")) return fail("no EGL_KHR_surfaceless_context");

    EGLConfig config = nullptr;
    if (!has_extension(extensions, "EGL_KHR_no_config_context")) {
        const EGLint attributes[] = {EGL_RENDERABLE_TYPE, out->gles ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_BIT, EGL_NONE};
        EGLint count = 0;
        if (!eglChooseConfig(display, attributes, &config, 1, &count) || count < 1) return fail("no OpenGL config");
    }
    const EGLint versions[][2] = {{4, 5}, {3, 3}};
    const EGLint es_versions[][2] = {{3, 0}};
    for (const auto& v : out->gles ? std::span<const EGLint[2]>(es_versions) : std::span<const EGLint[2]>(versions)) {
        const EGLint desktop[] = {EGL_CONTEXT_MAJOR_VERSION, v[0], EGL_CONTEXT_MINOR_VERSION, v[1],
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        const EGLint es[] = {EGL_CONTEXT_MAJOR_VERSION, v[0], EGL_CONTEXT_MINOR_VERSION, v[1], EGL_NONE};
        const EGLint* attributes = out->gles ? es : desktop;
        EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, attributes);
        if (context == EGL_NO_CONTEXT) continue;
        if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
            eglDestroyContext(display, context);
            continue;
        }
        out->display = display;
        out->context = context;
        out->platform = platform;
        return {};
    }
    return fail(std::string(out->gles ? "no OpenGL ES 3.0 context (" : "no OpenGL 3.3+ core context (") + egl_error_text() + ")");
}

std::string try_surfaceless(const char* client_extensions, PFNEGLGETPLATFORMDISPLAYEXTPROC get_display, GlContext* out) {
    if (!has_extension(client_extensions, "EGL_MESA_platform_surfaceless")) return "EGL surfaceless: not supported";
    return make_context(get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr), "EGL surfaceless", out);
}

// Tries every EGL device, hardware ones (those without
// EGL_MESA_device_software) first, or only those when `hardware_only`.
std::string try_devices(const char* client_extensions, PFNEGLGETPLATFORMDISPLAYEXTPROC get_display, bool hardware_only,
                        GlContext* out) {
    if (!has_extension(client_extensions, "EGL_EXT_platform_device")) return "EGL device: not supported";
    auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    auto query_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(eglGetProcAddress("eglQueryDeviceStringEXT"));
    if (!query_devices || !query_string) return "EGL device: no eglQueryDevicesEXT";
    EGLint count = 0;
    if (!query_devices(0, nullptr, &count) || count <= 0) return "EGL device: no devices";
    std::vector<EGLDeviceEXT> devices(std::size_t(count), nullptr);
    query_devices(count, devices.data(), &count);
    std::vector<int> order;
    for (int i = 0; i < count; ++i)
        if (!has_extension(query_string(devices[std::size_t(i)], EGL_EXTENSIONS), "EGL_MESA_device_software")) order.push_back(i);
    if (!hardware_only)
        for (int i = 0; i < count; ++i)
            if (has_extension(query_string(devices[std::size_t(i)], EGL_EXTENSIONS), "EGL_MESA_device_software")) order.push_back(i);
    if (order.empty()) return "EGL device: no hardware devices";
    std::string why;
    for (int i : order) {
        std::string name = "EGL device " + std::to_string(i);
        std::string error = make_context(get_display(EGL_PLATFORM_DEVICE_EXT, devices[std::size_t(i)], nullptr), name, out);
        if (error.empty()) return {};
        why += (why.empty() ? "" : "; ") + error;
    }
    return why;
}

} // namespace

std::string create_gl_context(GlPlatform platform, GlContext* out) {
    const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!client) return "EGL has no client extensions (is libEGL with Mesa installed?)";
    auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_display) return "EGL lacks eglGetPlatformDisplayEXT";
    std::string why;
    auto attempt = [&](const std::string& error) {
        if (error.empty()) return true;
        if (why.find(error) == std::string::npos) why += (why.empty() ? "" : "; ") + error;
        return false;
    };
    switch (platform) {
    case GlPlatform::surfaceless:
        attempt(try_surfaceless(client, get_display, out));
        break;
    case GlPlatform::device:
        attempt(try_devices(client, get_display, false, out));
        break;
    case GlPlatform::automatic:
        if (attempt(try_devices(client, get_display, true, out))) break;
        if (attempt(try_surfaceless(client, get_display, out))) break;
        attempt(try_devices(client, get_display, false, out));
        break;
    }
    return out->context != EGL_NO_CONTEXT ? std::string() : why;
}

} // namespace depthcull::render
