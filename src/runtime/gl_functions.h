// The GL entry points depthcull calls, in one table for the runtime
// renderer and the headless one in src/render (which links runtime): all
// in both OpenGL 3.3 core and OpenGL ES 3.0 (the query's 64-bit read is
// desktop-only and optional). The host's loader finds them (render's is
// eglGetProcAddress); we link no GL library, so one build serves any
// driver the host picked.
#pragma once

#include <GL/glcorearb.h>

#include <string>

#include "depthcull/runtime.h"

namespace depthcull::runtime {

#define DEPTHCULL_RUNTIME_GL(X)                                                                                            \
    X(PFNGLGETSTRINGPROC, GetString)                                                                                       \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                                                                                   \
    X(PFNGLGETERRORPROC, GetError)                                                                                         \
    X(PFNGLVIEWPORTPROC, Viewport)                                                                                         \
    X(PFNGLCLEARCOLORPROC, ClearColor)                                                                                     \
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
    X(PFNGLUSEPROGRAMPROC, UseProgram)                                                                                     \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                                                                     \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                                                                                       \
    X(PFNGLUNIFORM4FPROC, Uniform4f)                                                                                       \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                                                                           \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                                                                     \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                                                           \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                                                                                     \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                                                                               \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                                                                                     \
    X(PFNGLBUFFERDATAPROC, BufferData)                                                                                     \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                                                                               \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                                                   \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                                                           \
    X(PFNGLDRAWELEMENTSPROC, DrawElements)                                                                                 \
    X(PFNGLGENTEXTURESPROC, GenTextures)                                                                                   \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                                                                             \
    X(PFNGLBINDTEXTUREPROC, BindTexture)                                                                                   \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                                                                               \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                                                                     \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                                                               \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                                                                                   \
    X(PFNGLFINISHPROC, Finish)                                                                                             \
    X(PFNGLGENQUERIESPROC, GenQueries)                                                                                     \
    X(PFNGLDELETEQUERIESPROC, DeleteQueries)                                                                               \
    X(PFNGLBEGINQUERYPROC, BeginQuery)                                                                                     \
    X(PFNGLENDQUERYPROC, EndQuery)

// What a headless host adds (render's GlHost and GlRenderer): its own
// framebuffer, read-back, and GlRenderer's unindexed draws. An engine
// hosting the runtime renderer need not have them loaded.
#define DEPTHCULL_HOST_GL(X)                                                                                               \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                                                                           \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                                                                     \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                                                                           \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                                                                         \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                                                                   \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                                                                         \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                                                                   \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)                                                           \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)                                                             \
    X(PFNGLREADPIXELSPROC, ReadPixels)                                                                                     \
    X(PFNGLDRAWARRAYSPROC, DrawArrays)                                                                                     \
    X(PFNGLUNIFORM2FPROC, Uniform2f)

struct GlFunctions {
#define DEPTHCULL_RUNTIME_GL_MEMBER(type, name) type name = nullptr;
    DEPTHCULL_RUNTIME_GL(DEPTHCULL_RUNTIME_GL_MEMBER)
    DEPTHCULL_HOST_GL(DEPTHCULL_RUNTIME_GL_MEMBER)
#undef DEPTHCULL_RUNTIME_GL_MEMBER
    // Depth clear: glClearDepthf (ES, GL 4.1+) or glClearDepth (GL 3.3).
    PFNGLCLEARDEPTHFPROC ClearDepthf = nullptr;
    PFNGLCLEARDEPTHPROC ClearDepth = nullptr;
    // Desktop GL only (GL_SAMPLES_PASSED counts): absent on ES.
    PFNGLGETQUERYOBJECTUI64VPROC GetQueryObjectui64v = nullptr;

    // Empty on success, else the name of the first missing function;
    // with `host`, DEPTHCULL_HOST_GL's are required too.
    std::string load(GlLoader loader, bool host = false);
};

// ---- State and programs, shared by runtime::Renderer and render::GlRenderer
// so both draw with the same blend states and shader tail.

inline constexpr int kBlendCount = 4; // programs, indexed by int(Blend)

// GL state per (pass, blend): blending off for the opaque pass and
// Blend::opaque, else the Blend's factors (scene.h; docs/
// engine-integration.md lists them); depth writes in the opaque pass only
// when the meshes use the depth buffer.
void set_blend_state(const GlFunctions& gl, Pass pass, Blend blend, bool depth_test);

// One program per Blend: `header` (version line), the Blend's define,
// then `vertex`, or `fragment` + kBlendTail (shaders.h), which must leave
// the colour in a vec4 `c`. Empty on success, else a one-line reason;
// programs built before a failure stay in `programs` for the caller to
// delete.
std::string build_blend_programs(const GlFunctions& gl, const char* header, const char* vertex, const char* fragment,
                                 GLuint (&programs)[kBlendCount]);

// glGetString's text, "?" when GL gives none.
std::string gl_text(const GlFunctions& gl, GLenum name);

} // namespace depthcull::runtime
