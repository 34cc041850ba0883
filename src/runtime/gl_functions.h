// The GL entry points the runtime renderer calls, and nothing more: all in
// both OpenGL 3.3 core and OpenGL ES 3.0 (the query's 64-bit read is
// desktop-only and optional). The host's loader finds them; we link no GL
// library, so one build serves any driver the host picked.
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

struct GlFunctions {
#define DEPTHCULL_RUNTIME_GL_MEMBER(type, name) type name = nullptr;
    DEPTHCULL_RUNTIME_GL(DEPTHCULL_RUNTIME_GL_MEMBER)
#undef DEPTHCULL_RUNTIME_GL_MEMBER
    // Depth clear: glClearDepthf (ES, GL 4.1+) or glClearDepth (GL 3.3).
    PFNGLCLEARDEPTHFPROC ClearDepthf = nullptr;
    PFNGLCLEARDEPTHPROC ClearDepth = nullptr;
    // Desktop GL only (GL_SAMPLES_PASSED counts): absent on ES.
    PFNGLGETQUERYOBJECTUI64VPROC GetQueryObjectui64v = nullptr;

    // Empty on success, else the name of the first missing function.
    std::string load(GlLoader loader);
};

} // namespace depthcull::runtime
