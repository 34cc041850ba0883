// The EGL side of the headless renderers: a context with no surface. The
// GL entry points, blend states and shader tail are runtime's
// (runtime/gl_functions.h), loaded through eglGetProcAddress: one table
// for render and runtime.
#pragma once

#include <EGL/egl.h>

#include <string>

#include "depthcull/render.h"
#include "runtime/gl_functions.h"

namespace depthcull::render {

// An EGL display + context made current on this thread, no surface.
struct GlContext {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    std::string platform; // "EGL surfaceless" / "EGL device 0"
    bool gles = false;    // input: an OpenGL ES 3.0 context instead of desktop GL core
    void destroy();
};

// Empty on success, else why no context could be made (every try listed).
std::string create_gl_context(GlPlatform platform, GlContext* out);

} // namespace depthcull::render
