// The OpenGL entry points the renderer uses, loaded with eglGetProcAddress
// (no loader library in Debian we may depend on, and linking GL functions
// directly would tie us to one vendor's libGL).
#pragma once

#include <EGL/egl.h>
#include <GL/glcorearb.h>

#include <string>

#include "depthcull/render.h"

namespace depthcull::render {

#define DEPTHCULL_GL_FUNCTIONS(X)                                                                                          \
    X(PFNGLGETSTRINGPROC, GetString)                                                                                       \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                                                   \
    X(PFNGLGETERRORPROC, GetError)                                                                                         \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                                                                           \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                                                     \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                                                           \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                                                                         \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                                                                   \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                                                                         \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                                                                   \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)                                                           \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                                                             \
    X(PFNGLVIEWPORTPROC, Viewport)                                                                                         \
    X(PFNGLCLEARCOLORPROC, ClearColor)                                                                                     \
    X(PFNGLCLEARDEPTHPROC, ClearDepth)                                                                                     \
    X(PFNGLCLEARPROC, Clear)                                                                                               \
    X(PFNGLENABLEPROC, Enable)                                                                                             \
    X(PFNGLDISABLEPROC, Disable)                                                                                           \
    X(PFNGLDEPTHFUNCPROC, DepthFunc)                                                                                       \
    X(PFNGLDEPTHMASKPROC, DepthMask)                                                                                       \
    X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate)                                                                       \
    X(PFNGLBLENDEQUATIONPROC, BlendEquation)                                                                               \
    X(PFNGLCREATESHADERPROC, CreateShader)                                                                                 \
    X(PFNGLDELETESHADERPROC, DeleteShader)                                                                                 \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                                                                                 \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                                                                               \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                                                                                   \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                                                                         \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                                                                               \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                                                                               \
    X(PFNGLATTACHSHADERPROC, AttachShader)                                                                                 \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                                                                                   \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                                                                                 \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                                                                       \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                                                                                     \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                                                     \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                                                                                       \
    X(PFNGLUNIFORM2FPROC, Uniform2f)                                                                                       \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                                                                           \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                                                     \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                                                           \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                                                                                     \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                                                               \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                                                                                     \
    X(PFNGLBUFFERDATAPROC, BufferData)                                                                                     \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                                                   \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                                                           \
    X(PFNGLDRAWARRAYSPROC, DrawArrays)                                                                                     \
    X(PFNGLGENTEXTURESPROC, GenTextures)                                                                                   \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                                                             \
    X(PFNGLBINDTEXTUREPROC, BindTexture)                                                                                   \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                                                               \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                                                                     \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                                                               \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                                                   \
    X(PFNGLREADPIXELSPROC, ReadPixels)                                                                                     \
    X(PFNGLFINISHPROC, Finish)                                                                                             \
    X(PFNGLGENQUERIESPROC, GenQueries)                                                                                     \
    X(PFNGLDELETEQUERIESPROC, DeleteQueries)                                                                               \
    X(PFNGLBEGINQUERYPROC, BeginQuery)                                                                                     \
    X(PFNGLENDQUERYPROC, EndQuery)                                                                                         \
    X(PFNGLGETQUERYOBJECTUI64VPROC, GetQueryObjectui64v)

struct Gl {
#define DEPTHCULL_GL_MEMBER(type, name) type name = nullptr;
    DEPTHCULL_GL_FUNCTIONS(DEPTHCULL_GL_MEMBER)
#undef DEPTHCULL_GL_MEMBER

    // Empty on success, else the name of the first missing function.
    std::string load();
};

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
