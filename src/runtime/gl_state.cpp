// The GL plumbing runtime::Renderer and render::GlRenderer share: loading
// the function table, blend state per (pass, blend), and building one
// program per Blend around the common shader tail. One definition each,
// so the headless renderer that proves pixel identity and the one engines
// link cannot drift apart.
#include "runtime/gl_functions.h"
#include "runtime/shaders.h"

namespace depthcull::runtime {

std::string GlFunctions::load(GlLoader loader, bool host) {
#define DEPTHCULL_RUNTIME_GL_LOAD(type, name)                                                                              \
    name = reinterpret_cast<type>(loader("gl" #name));                                                                     \
    if (!name) return "gl" #name;
    DEPTHCULL_RUNTIME_GL(DEPTHCULL_RUNTIME_GL_LOAD)
    if (host) {
        DEPTHCULL_HOST_GL(DEPTHCULL_RUNTIME_GL_LOAD)
    }
#undef DEPTHCULL_RUNTIME_GL_LOAD
    ClearDepthf = reinterpret_cast<PFNGLCLEARDEPTHFPROC>(loader("glClearDepthf"));
    ClearDepth = reinterpret_cast<PFNGLCLEARDEPTHPROC>(loader("glClearDepth"));
    if (!ClearDepthf && !ClearDepth) return "glClearDepthf";
    GetQueryObjectui64v = reinterpret_cast<PFNGLGETQUERYOBJECTUI64VPROC>(loader("glGetQueryObjectui64v"));
    return {};
}

void set_blend_state(const GlFunctions& gl, Pass pass, Blend blend, bool depth_test) {
    if (pass == Pass::opaque || blend == Blend::opaque) {
        gl.Disable(GL_BLEND);
    } else {
        gl.Enable(GL_BLEND);
        switch (blend) {
        case Blend::alpha:
            gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
            break;
        case Blend::add:
            gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE, GL_SRC_ALPHA, GL_ONE);
            break;
        case Blend::multiply:
            gl.BlendFuncSeparate(GL_DST_COLOR, GL_ONE_MINUS_SRC_ALPHA, GL_DST_COLOR, GL_ONE_MINUS_SRC_ALPHA);
            break;
        case Blend::opaque:
            break;
        }
    }
    if (depth_test) gl.DepthMask(pass == Pass::opaque ? GL_TRUE : GL_FALSE);
}

namespace {

// 0 and *error set (the log on one line) when it does not compile.
GLuint compile(const GlFunctions& gl, GLenum type, const char* const* parts, GLsizei count, std::string* error) {
    GLuint shader = gl.CreateShader(type);
    gl.ShaderSource(shader, count, parts, nullptr);
    gl.CompileShader(shader);
    GLint ok = 0;
    gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[512] = {};
        gl.GetShaderInfoLog(shader, sizeof log, nullptr, log);
        for (char& c : log)
            if (c == '\n') c = ' ';
        *error = std::string("shader does not compile: ") + log;
        gl.DeleteShader(shader);
        return 0;
    }
    return shader;
}

} // namespace

std::string build_blend_programs(const GlFunctions& gl, const char* header, const char* vertex, const char* fragment,
                                 GLuint (&programs)[kBlendCount]) {
    std::string error;
    for (int b = 0; b < kBlendCount; ++b) {
        const char* vertex_parts[] = {header, vertex};
        const char* fragment_parts[] = {header, kBlendDefines[b], fragment, kBlendTail};
        GLuint vs = compile(gl, GL_VERTEX_SHADER, vertex_parts, 2, &error);
        GLuint fs = vs ? compile(gl, GL_FRAGMENT_SHADER, fragment_parts, 4, &error) : 0;
        if (!vs || !fs) {
            if (vs) gl.DeleteShader(vs);
            return error;
        }
        GLuint program = gl.CreateProgram();
        gl.AttachShader(program, vs);
        gl.AttachShader(program, fs);
        gl.LinkProgram(program);
        gl.DeleteShader(vs);
        gl.DeleteShader(fs);
        programs[b] = program;
        GLint ok = 0;
        gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
        if (!ok) return "shader program does not link";
        gl.UseProgram(program);
        gl.Uniform1i(gl.GetUniformLocation(program, "u_texture"), 0);
    }
    return {};
}

std::string gl_text(const GlFunctions& gl, GLenum name) {
    const GLubyte* s = gl.GetString(name);
    return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
}

} // namespace depthcull::runtime
