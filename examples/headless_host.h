#pragma once
// The examples' "engine": a GL context current on this thread and an
// offscreen framebuffer, through EGL's surfaceless platform (no window).
// Yours has SDL, GLFW or a platform layer instead; the examples share this
// one so each reads as the frame loop alone.
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <cstddef>

#include "depthcull/image.h"

namespace example {

using depthcull::Image;

// ---- The host: a GL context current on this thread, and a framebuffer
// with a depth buffer. This is the part your engine already has.
struct Host {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    GLuint framebuffer = 0;
    PFNGLREADPIXELSPROC ReadPixels = nullptr;

    bool open(int width, int height) {
        auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
        if (!get_display) return false;
        display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (display == EGL_NO_DISPLAY || !eglInitialize(display, nullptr, nullptr) || !eglBindAPI(EGL_OPENGL_API)) return false;
        const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                     EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
        if (context == EGL_NO_CONTEXT || !eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) return false;

        // No window, so render into an RGBA8 + 24-bit depth framebuffer.
        auto load = [](const char* name) { return eglGetProcAddress(name); };
        auto GenFramebuffers = reinterpret_cast<PFNGLGENFRAMEBUFFERSPROC>(load("glGenFramebuffers"));
        auto BindFramebuffer = reinterpret_cast<PFNGLBINDFRAMEBUFFERPROC>(load("glBindFramebuffer"));
        auto GenRenderbuffers = reinterpret_cast<PFNGLGENRENDERBUFFERSPROC>(load("glGenRenderbuffers"));
        auto BindRenderbuffer = reinterpret_cast<PFNGLBINDRENDERBUFFERPROC>(load("glBindRenderbuffer"));
        auto RenderbufferStorage = reinterpret_cast<PFNGLRENDERBUFFERSTORAGEPROC>(load("glRenderbufferStorage"));
        auto FramebufferRenderbuffer = reinterpret_cast<PFNGLFRAMEBUFFERRENDERBUFFERPROC>(load("glFramebufferRenderbuffer"));
        auto PixelStorei = reinterpret_cast<PFNGLPIXELSTOREIPROC>(load("glPixelStorei"));
        ReadPixels = reinterpret_cast<PFNGLREADPIXELSPROC>(load("glReadPixels"));
        if (!GenFramebuffers || !ReadPixels) return false;
        GLuint buffers[2];
        GenRenderbuffers(2, buffers);
        BindRenderbuffer(GL_RENDERBUFFER, buffers[0]);
        RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
        BindRenderbuffer(GL_RENDERBUFFER, buffers[1]);
        RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
        GenFramebuffers(1, &framebuffer);
        BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
        FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, buffers[0]);
        FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, buffers[1]);
        PixelStorei(GL_PACK_ALIGNMENT, 1);
        return true;
    }

    Image read(int width, int height) const {
        Image image;
        image.width = width;
        image.height = height;
        image.rgba.resize(std::size_t(width) * std::size_t(height) * 4);
        ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
        return image;
    }
};

// The loader the runtime gets: any function from a name to an address.
inline void* gl_loader(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

} // namespace example
