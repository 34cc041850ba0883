// GlHost: the host side of depthcull::runtime without a window, an EGL
// context and an offscreen framebuffer; GlRenderer draws into one too.
// Its GL functions are runtime's table with the host's (framebuffer
// objects, read-back) required; the runtime loads its own through
// get_proc_address, as it would from an engine.
#include "render/gl.h"

namespace depthcull::render {

struct GlHost::Impl {
    GlContext context;
    runtime::GlFunctions gl;
    std::string description;
    bool software = false;
    GLuint framebuffer = 0, color = 0, depth = 0;
    int width = 0, height = 0;

    ~Impl() {
        if (context.context != EGL_NO_CONTEXT && gl.DeleteFramebuffers) {
            make_current();
            if (framebuffer) gl.DeleteFramebuffers(1, &framebuffer);
            if (color) gl.DeleteRenderbuffers(1, &color);
            if (depth) gl.DeleteRenderbuffers(1, &depth);
        }
        context.destroy();
    }

    void make_current() {
        // EGL keeps one current context per client API: bind ours first.
        eglBindAPI(context.gles ? EGL_OPENGL_ES_API : EGL_OPENGL_API);
        if (eglGetCurrentContext() != context.context)
            eglMakeCurrent(context.display, EGL_NO_SURFACE, EGL_NO_SURFACE, context.context);
    }
};

GlHost::GlHost(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GlHost::~GlHost() = default;

std::unique_ptr<GlHost> GlHost::create(const GlOptions& options, GlApi api) {
    auto impl = std::make_unique<Impl>();
    impl->context.gles = api == GlApi::gles;
    std::string why = create_gl_context(options.platform, &impl->context);
    if (why.empty()) {
        std::string missing = impl->gl.load(&GlHost::get_proc_address, true);
        if (!missing.empty()) why = impl->context.platform + ": GL lacks " + missing;
    }
    if (!why.empty()) throw NoContext("no OpenGL context: " + why);
    auto text = [&](GLenum name) { return runtime::gl_text(impl->gl, name); };
    const std::string renderer = text(GL_RENDERER);
    impl->description = renderer + ", " + (api == GlApi::gles ? "" : "OpenGL ") + text(GL_VERSION) + ", " + impl->context.platform;
    impl->software = renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos;
    impl->gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    return std::unique_ptr<GlHost>(new GlHost(std::move(impl)));
}

void* GlHost::get_proc_address(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }
const std::string& GlHost::description() const { return impl_->description; }
bool GlHost::is_software() const { return impl_->software; }
void GlHost::make_current() { impl_->make_current(); }
void GlHost::finish() { impl_->gl.Finish(); }

void GlHost::bind_framebuffer(int w, int h) {
    Impl& r = *impl_;
    r.make_current();
    runtime::GlFunctions& gl = r.gl;
    if (w != r.width || h != r.height || !r.framebuffer) {
        GLint max_size = 0;
        gl.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
        if (w <= 0 || h <= 0 || w > max_size || h > max_size)
            throw Error("viewport " + std::to_string(w) + "x" + std::to_string(h) + " is outside this GL's framebuffer limit " +
                        std::to_string(max_size));
        if (!r.framebuffer) {
            gl.GenFramebuffers(1, &r.framebuffer);
            gl.GenRenderbuffers(1, &r.color);
            gl.GenRenderbuffers(1, &r.depth);
        }
        gl.BindRenderbuffer(GL_RENDERBUFFER, r.color);
        gl.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
        gl.BindRenderbuffer(GL_RENDERBUFFER, r.depth);
        gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, w, h);
        gl.BindFramebuffer(GL_FRAMEBUFFER, r.framebuffer);
        gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, r.color);
        gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r.depth);
        if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            throw Error("GL framebuffer RGBA8 + DEPTH_COMPONENT24 is incomplete");
        r.width = w;
        r.height = h;
    }
    gl.BindFramebuffer(GL_FRAMEBUFFER, r.framebuffer);
}

Image GlHost::read_pixels() {
    Impl& r = *impl_;
    r.make_current();
    Image image;
    image.width = r.width;
    image.height = r.height;
    image.rgba.resize(std::size_t(r.width) * std::size_t(r.height) * 4);
    r.gl.BindFramebuffer(GL_FRAMEBUFFER, r.framebuffer);
    r.gl.ReadPixels(0, 0, r.width, r.height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    return image;
}

} // namespace depthcull::render
