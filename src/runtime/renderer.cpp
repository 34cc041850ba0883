// depthcull::runtime::Renderer: the two-pass depth-buffer 2D renderer of
// paper 2.3.3 as an engine runs it. Static meshes live in one vertex and
// one index buffer uploaded once; each frame uploads only the dynamic
// draws, into buffers reserved ahead, and issues one glDrawElements per
// Draw. Nothing in a frame allocates (tests/runtime counts operator new).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <ctime>

#include "runtime/gl_functions.h"
#include "runtime/shaders.h"

namespace depthcull::runtime {

namespace {

constexpr GLenum kSamplesPassed = 0x8914; // GL_SAMPLES_PASSED (desktop GL only)

// One glDrawElements: `count` indices from byte `offset` of the index buffer.
struct Batch {
    int image = 0;
    Pass pass = Pass::blend;
    Blend blend = Blend::alpha;
    std::size_t offset = 0, count = 0;
};

double process_cpu_ms() {
#if defined(CLOCK_PROCESS_CPUTIME_ID)
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
#else
    return double(std::clock()) * 1e3 / CLOCKS_PER_SEC;
#endif
}

} // namespace

struct Renderer::Impl {
    GlFunctions gl;
    bool gles = false;
    std::string version, error;
    GLuint programs[kBlendCount] = {};
    GLint camera_location[kBlendCount] = {}, scale_location[kBlendCount] = {};
    std::vector<GLuint> textures;
    bool own_textures = false;
    GLuint query = 0;

    // Static meshes.
    GLuint static_vao = 0, static_vertices = 0, static_indices = 0;
    std::vector<Batch> static_batches;
    std::vector<std::size_t> static_batch_of_draw; // per static draw (and one past): its first batch
    bool depth_test = false;
    std::int64_t static_triangles = 0;

    // Dynamic draws: CPU staging and GL buffers, both kept at capacity.
    GLuint dynamic_vao = 0, dynamic_vertices = 0, dynamic_indices = 0;
    std::vector<float> staging_vertices;
    std::vector<std::uint32_t> staging_indices;
    std::vector<Batch> dynamic_batches;
    std::size_t gl_vertex_capacity = 0, gl_index_capacity = 0; // in floats / indices

    Status fail(Status s, std::string message) {
        error = std::move(message);
        return s;
    }

    Status check_gl(const char* what) {
        if (GLenum e = gl.GetError(); e != GL_NO_ERROR) return fail(Status::gl_error, "GL error " + std::to_string(e) + " " + what);
        return Status::ok;
    }

    Status build_programs() {
        if (std::string why = build_blend_programs(gl, gles ? kEsHeader : kDesktopHeader, kVertexShader, kFragmentShader, programs);
            !why.empty())
            return fail(Status::shader_failed, why);
        for (int b = 0; b < kBlendCount; ++b) {
            camera_location[b] = gl.GetUniformLocation(programs[b], "u_camera");
            scale_location[b] = gl.GetUniformLocation(programs[b], "u_scale_offset");
        }
        return check_gl("building shaders");
    }

    // Position (3), uv (2), colour (4): SceneMeshes' own vertex layout, so
    // vertices go to GL as they are.
    void set_attributes(GLuint vao, GLuint vertices, GLuint indices) {
        gl.BindVertexArray(vao);
        gl.BindBuffer(GL_ARRAY_BUFFER, vertices);
        gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices);
        const GLsizei stride = kVertexFloats * sizeof(float);
        const int sizes[3] = {3, 2, 4};
        for (GLuint i = 0, offset = 0; i < 3; offset += GLuint(sizes[i]), ++i) {
            gl.VertexAttribPointer(i, sizes[i], GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(std::uintptr_t(offset * sizeof(float))));
            gl.EnableVertexAttribArray(i);
        }
    }

    void delete_textures() {
        if (own_textures && !textures.empty()) gl.DeleteTextures(GLsizei(textures.size()), textures.data());
        textures.clear();
        own_textures = false;
    }

    // Appends d's vertices and its indices rebased to `base` (in vertices).
    static void append_draw(const Draw& d, std::vector<float>& vertices, std::vector<std::uint32_t>& indices) {
        const auto base = std::uint32_t(vertices.size() / kVertexFloats);
        vertices.insert(vertices.end(), d.vertices.begin(), d.vertices.end());
        for (std::uint32_t i : d.indices) indices.push_back(base + i);
    }

    Status validate(const Draw& d) {
        if (d.image < 0 || std::size_t(d.image) >= textures.size())
            return fail(Status::bad_meshes, "draw names image " + std::to_string(d.image) + " but " + std::to_string(textures.size()) +
                                                " textures are set");
        if (d.vertices.size() % kVertexFloats != 0) return fail(Status::bad_meshes, "draw has a partial vertex");
        const std::size_t n = d.vertex_count();
        for (std::uint32_t i : d.indices)
            if (i >= n) return fail(Status::bad_meshes, "draw has index " + std::to_string(i) + " past its " + std::to_string(n) + " vertices");
        return Status::ok;
    }

    struct Bound {
        int program = -1;
        int image = -1;
        int vao = -1; // 0 static, 1 dynamic
    };

    void draw_batches(const std::vector<Batch>& batches, std::size_t begin, std::size_t end, int vao, Bound& bound,
                      const Camera& camera, FrameCounts& counts) {
        for (std::size_t k = begin; k < end; ++k) {
            const Batch& b = batches[k];
            if (vao != bound.vao) {
                gl.BindVertexArray(vao == 0 ? static_vao : dynamic_vao);
                bound.vao = vao;
            }
            const int program = int(b.blend);
            if (program != bound.program) {
                gl.UseProgram(programs[program]);
                gl.Uniform4f(camera_location[program], float(camera.x), float(camera.y), 0, 0);
                const float sy = camera.flip_y ? -2.0f : 2.0f;
                gl.Uniform4f(scale_location[program], 2.0f / float(camera.width), sy / float(camera.height), -1.0f,
                             camera.flip_y ? 1.0f : -1.0f);
                bound.program = program;
            }
            if (b.image != bound.image) {
                gl.BindTexture(GL_TEXTURE_2D, textures[std::size_t(b.image)]);
                bound.image = b.image;
            }
            set_blend_state(gl, b.pass, b.blend, depth_test);
            gl.DrawElements(GL_TRIANGLES, GLsizei(b.count), GL_UNSIGNED_INT, reinterpret_cast<const void*>(b.offset));
            ++counts.draw_calls;
            counts.triangles += std::int64_t(b.count / 3);
        }
    }

    Status upload_dynamic(std::span<const Draw> dynamic) {
        staging_vertices.clear();
        staging_indices.clear();
        dynamic_batches.clear();
        // Opaque draws first, then blend: the order they are drawn in.
        for (int pass = 0; pass < 2; ++pass)
            for (const Draw& d : dynamic) {
                if ((d.pass == Pass::opaque) != (pass == 0) || d.indices.empty()) continue;
                if (Status s = validate(d); s != Status::ok) return s;
                const std::size_t first = staging_indices.size();
                append_draw(d, staging_vertices, staging_indices);
                dynamic_batches.push_back({d.image, d.pass, d.blend, first * sizeof(std::uint32_t), d.indices.size()});
            }
        if (dynamic_batches.empty()) return Status::ok;
        gl.BindVertexArray(dynamic_vao);
        gl.BindBuffer(GL_ARRAY_BUFFER, dynamic_vertices);
        // Orphan and refill: the driver hands us fresh storage instead of
        // waiting for the last frame's draws to finish reading the old one.
        if (staging_vertices.size() > gl_vertex_capacity) gl_vertex_capacity = staging_vertices.capacity();
        if (staging_indices.size() > gl_index_capacity) gl_index_capacity = staging_indices.capacity();
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(gl_vertex_capacity * sizeof(float)), nullptr, GL_STREAM_DRAW);
        gl.BufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(staging_vertices.size() * sizeof(float)), staging_vertices.data());
        gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(gl_index_capacity * sizeof(std::uint32_t)), nullptr, GL_STREAM_DRAW);
        gl.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, GLsizeiptr(staging_indices.size() * sizeof(std::uint32_t)), staging_indices.data());
        return Status::ok;
    }

    // Starts a frame: the samples query (when counted), the viewport, the
    // clears and the depth test. Larger z is nearer (scene.h), so depth is
    // cleared to 0, the farthest. Returns whether samples are counted.
    bool begin_frame(const Camera& camera, const FrameOptions& options, bool use_depth) {
        const bool counting = options.count_samples && gl.GetQueryObjectui64v && !gles;
        if (counting) gl.BeginQuery(kSamplesPassed, query);
        gl.Viewport(0, 0, camera.width, camera.height);
        GLbitfield clear = 0;
        if (options.clear_color) {
            gl.ClearColor(0, 0, 0, 0);
            clear |= GL_COLOR_BUFFER_BIT;
        }
        if (use_depth) {
            gl.DepthMask(GL_TRUE);
            if (gl.ClearDepthf) gl.ClearDepthf(0.0f);
            else gl.ClearDepth(0.0);
            clear |= GL_DEPTH_BUFFER_BIT;
        }
        if (clear) gl.Clear(clear);
        if (use_depth && !options.no_depth_test) {
            gl.Enable(GL_DEPTH_TEST);
            gl.DepthFunc(GL_GREATER);
        } else {
            gl.Disable(GL_DEPTH_TEST);
        }
        return counting;
    }

    Status draw(const Camera& camera, std::span<const Draw> dynamic, const FrameOptions& options, FrameCounts* out) {
        if (camera.width <= 0 || camera.height <= 0) return fail(Status::bad_meshes, "camera has no pixels");
        if (Status s = upload_dynamic(dynamic); s != Status::ok) return s;
        const bool counting = begin_frame(camera, options, depth_test);
        gl.ActiveTexture(GL_TEXTURE0);
        FrameCounts counts;
        Bound bound;
        const std::size_t dynamic_opaque = std::size_t(
            std::count_if(dynamic_batches.begin(), dynamic_batches.end(), [](const Batch& b) { return b.pass == Pass::opaque; }));
        draw_batches(dynamic_batches, 0, dynamic_opaque, 1, bound, camera, counts);
        draw_batches(static_batches, 0, static_batches.size(), 0, bound, camera, counts);
        draw_batches(dynamic_batches, dynamic_opaque, dynamic_batches.size(), 1, bound, camera, counts);
        if (counting) {
            gl.EndQuery(kSamplesPassed);
            GLuint64 samples = 0;
            gl.GetQueryObjectui64v(query, GL_QUERY_RESULT, &samples);
            counts.samples_passed = std::int64_t(samples);
        }
        if (out) *out = counts;
        return Status::ok;
    }

    // An assembled frame (depthcull/frame.h): its opaque draws, the static
    // opaque draws, then the static blend draws with each insertion point's
    // blend draws between them. Uploads the frame's buffers as they are.
    Status draw_frame(const Camera& camera, const AssembledFrame& frame, const FrameOptions& options, FrameCounts* out) {
        if (camera.width <= 0 || camera.height <= 0) return fail(Status::bad_meshes, "camera has no pixels");
        const std::size_t vertex_count = frame.vertices.size() / kVertexFloats;
        if (frame.vertices.size() % kVertexFloats != 0 || frame.opaque_draws > frame.draws.size())
            return fail(Status::bad_meshes, "assembled frame is inconsistent");
        dynamic_batches.clear();
        for (const FrameDraw& d : frame.draws) {
            if (d.image < 0 || std::size_t(d.image) >= textures.size())
                return fail(Status::bad_meshes, "frame draw names image " + std::to_string(d.image) + " but " +
                                                    std::to_string(textures.size()) + " textures are set");
            if (std::size_t(d.first_index) + d.index_count > frame.indices.size())
                return fail(Status::bad_meshes, "frame draw runs past the frame's indices");
            dynamic_batches.push_back({d.image, d.pass, d.blend, std::size_t(d.first_index) * sizeof(std::uint32_t), d.index_count});
        }
        for (std::uint32_t i : frame.indices)
            if (i >= vertex_count) return fail(Status::bad_meshes, "frame has index " + std::to_string(i) + " past its vertices");
        for (const FramePoint& p : frame.points)
            if (p.first_draw > p.end_draw || p.end_draw > frame.draws.size() || p.first_draw < frame.opaque_draws)
                return fail(Status::bad_meshes, "frame point names draws that do not exist");
        if (!frame.vertices.empty()) {
            gl.BindVertexArray(dynamic_vao);
            gl.BindBuffer(GL_ARRAY_BUFFER, dynamic_vertices);
            gl_vertex_capacity = std::max(gl_vertex_capacity, frame.vertices.capacity());
            gl_index_capacity = std::max(gl_index_capacity, frame.indices.capacity());
            gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(gl_vertex_capacity * sizeof(float)), nullptr, GL_STREAM_DRAW);
            gl.BufferSubData(GL_ARRAY_BUFFER, 0, GLsizeiptr(frame.vertices.size() * sizeof(float)), frame.vertices.data());
            gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(gl_index_capacity * sizeof(std::uint32_t)), nullptr, GL_STREAM_DRAW);
            gl.BufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, GLsizeiptr(frame.indices.size() * sizeof(std::uint32_t)), frame.indices.data());
        }
        const bool use_depth = depth_test || (frame.depth_test && frame.opaque_draws > 0);
        const bool counting = begin_frame(camera, options, use_depth);
        // set_state sets the depth mask only when the static meshes use depth.
        const bool static_depth = depth_test;
        depth_test = use_depth;
        gl.ActiveTexture(GL_TEXTURE0);
        FrameCounts counts;
        Bound bound;
        std::size_t static_blend = std::size_t(
            std::count_if(static_batches.begin(), static_batches.end(), [](const Batch& b) { return b.pass == Pass::opaque; }));
        draw_batches(dynamic_batches, 0, frame.opaque_draws, 1, bound, camera, counts);
        draw_batches(static_batches, 0, static_blend, 0, bound, camera, counts);
        for (const FramePoint& p : frame.points) {
            const std::size_t until = p.static_draw < static_batch_of_draw.size() ? static_batch_of_draw[p.static_draw] : static_batches.size();
            if (until > static_blend) {
                draw_batches(static_batches, static_blend, until, 0, bound, camera, counts);
                static_blend = until;
            }
            draw_batches(dynamic_batches, p.first_draw, p.end_draw, 1, bound, camera, counts);
        }
        draw_batches(static_batches, static_blend, static_batches.size(), 0, bound, camera, counts);
        depth_test = static_depth;
        if (counting) {
            gl.EndQuery(kSamplesPassed);
            GLuint64 samples = 0;
            gl.GetQueryObjectui64v(query, GL_QUERY_RESULT, &samples);
            counts.samples_passed = std::int64_t(samples);
        }
        if (out) *out = counts;
        return check_gl("drawing a frame");
    }

    void delete_meshes() {
        if (static_vao) gl.DeleteVertexArrays(1, &static_vao);
        if (static_vertices) gl.DeleteBuffers(1, &static_vertices);
        if (static_indices) gl.DeleteBuffers(1, &static_indices);
        static_vao = static_vertices = static_indices = 0;
        static_batches.clear();
        static_batch_of_draw.clear();
        static_triangles = 0;
    }

    ~Impl() {
        if (!gl.DeleteProgram) return;
        for (GLuint p : programs)
            if (p) gl.DeleteProgram(p);
        delete_textures();
        delete_meshes();
        if (dynamic_vao) gl.DeleteVertexArrays(1, &dynamic_vao);
        if (dynamic_vertices) gl.DeleteBuffers(1, &dynamic_vertices);
        if (dynamic_indices) gl.DeleteBuffers(1, &dynamic_indices);
        if (query) gl.DeleteQueries(1, &query);
    }
};

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::~Renderer() = default;

std::unique_ptr<Renderer> Renderer::create(GlLoader loader, std::string* error) {
    auto set_error = [&](const std::string& why) {
        if (error) *error = "no OpenGL: " + why;
        return nullptr;
    };
    if (!loader) return set_error("no loader given");
    auto impl = std::make_unique<Impl>();
    GlFunctions& gl = impl->gl;
    if (std::string missing = gl.load(loader); !missing.empty()) {
        gl.DeleteProgram = nullptr; // nothing was created
        return set_error("the context lacks " + missing + " (is a GL 3.3 / ES 3.0 context current?)");
    }
    const GLubyte* text = gl.GetString(GL_VERSION);
    impl->version = text ? reinterpret_cast<const char*>(text) : "";
    impl->gles = impl->version.rfind("OpenGL ES", 0) == 0;
    GLint major = 0;
    gl.GetIntegerv(GL_MAJOR_VERSION, &major);
    if (major < 3) return set_error("the context is OpenGL " + impl->version + ", older than 3.3 / ES 3.0");
    if (impl->build_programs() != Status::ok) return set_error(impl->error);
    gl.GenVertexArrays(1, &impl->dynamic_vao);
    gl.GenBuffers(1, &impl->dynamic_vertices);
    gl.GenBuffers(1, &impl->dynamic_indices);
    impl->set_attributes(impl->dynamic_vao, impl->dynamic_vertices, impl->dynamic_indices);
    if (!impl->gles) gl.GenQueries(1, &impl->query);
    if (impl->check_gl("setting up") != Status::ok) return set_error(impl->error);
    return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

const std::string& Renderer::gl_version() const { return impl_->version; }
bool Renderer::is_gles() const { return impl_->gles; }
const std::string& Renderer::error() const { return impl_->error; }
const std::vector<unsigned>& Renderer::texture_names() const { return impl_->textures; }

Status Renderer::upload_images(std::span<const ImageView> images, Filter filter) {
    Impl& r = *impl_;
    GlFunctions& gl = r.gl;
    GLint max_size = 0;
    gl.GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    for (std::size_t i = 0; i < images.size(); ++i) {
        const ImageView& v = images[i];
        if (!v.rgba || v.width <= 0 || v.height <= 0 || v.width > max_size || v.height > max_size || v.stride < std::ptrdiff_t(v.width) * 4 ||
            v.stride % 4 != 0)
            return r.fail(Status::bad_image, "image " + std::to_string(i) + " (" + std::to_string(v.width) + "x" + std::to_string(v.height) +
                                                 ") is empty or outside this GL's texture limit " + std::to_string(max_size));
    }
    r.delete_textures();
    r.textures.assign(images.size(), 0);
    r.own_textures = true;
    if (!images.empty()) gl.GenTextures(GLsizei(images.size()), r.textures.data());
    const GLint mode = filter == Filter::linear ? GL_LINEAR : GL_NEAREST;
    gl.ActiveTexture(GL_TEXTURE0);
    for (std::size_t i = 0; i < images.size(); ++i) {
        const ImageView& v = images[i];
        gl.BindTexture(GL_TEXTURE_2D, r.textures[i]);
        gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
        gl.PixelStorei(GL_UNPACK_ROW_LENGTH, GLint(v.stride / 4));
        gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, v.width, v.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, v.rgba);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, mode);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, mode);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    gl.PixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    return r.check_gl("uploading textures");
}

Status Renderer::set_textures(std::span<const unsigned> names) {
    impl_->delete_textures();
    impl_->textures.assign(names.begin(), names.end());
    return Status::ok;
}

Status Renderer::set_meshes(const SceneMeshes& meshes) {
    Impl& r = *impl_;
    GlFunctions& gl = r.gl;
    std::vector<float> vertices;
    std::vector<std::uint32_t> indices;
    std::vector<Batch> batches;
    std::vector<std::size_t> batch_of_draw;
    for (const Draw& d : meshes.draws) {
        if (Status s = r.validate(d); s != Status::ok) return s;
        batch_of_draw.push_back(batches.size());
        if (d.indices.empty()) continue;
        if (vertices.size() / kVertexFloats + d.vertex_count() > std::size_t(UINT32_MAX))
            return r.fail(Status::bad_meshes, "meshes have more than 2^32 vertices");
        batches.push_back({d.image, d.pass, d.blend, indices.size() * sizeof(std::uint32_t), d.indices.size()});
        Impl::append_draw(d, vertices, indices);
    }
    r.delete_meshes();
    r.depth_test = meshes.depth_test;
    r.static_batches = std::move(batches);
    batch_of_draw.push_back(r.static_batches.size());
    r.static_batch_of_draw = std::move(batch_of_draw);
    gl.GenVertexArrays(1, &r.static_vao);
    gl.GenBuffers(1, &r.static_vertices);
    gl.GenBuffers(1, &r.static_indices);
    r.set_attributes(r.static_vao, r.static_vertices, r.static_indices);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data(), GL_STATIC_DRAW);
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(), GL_STATIC_DRAW);
    gl.BindVertexArray(0);
    // Room for as many dynamic batches as the static meshes have draws,
    // so a typical frame's list never grows.
    r.dynamic_batches.reserve(std::max<std::size_t>(r.dynamic_batches.capacity(), 64));
    return r.check_gl("uploading meshes");
}

Status Renderer::reserve_dynamic(std::size_t vertices, std::size_t indices) {
    Impl& r = *impl_;
    r.staging_vertices.reserve(vertices * kVertexFloats);
    r.staging_indices.reserve(indices);
    r.dynamic_batches.reserve(std::max<std::size_t>(r.dynamic_batches.capacity(), indices / 3 + 1));
    r.gl_vertex_capacity = std::max(r.gl_vertex_capacity, r.staging_vertices.capacity());
    r.gl_index_capacity = std::max(r.gl_index_capacity, r.staging_indices.capacity());
    return Status::ok;
}

Status Renderer::draw(const Camera& camera, std::span<const Draw> dynamic, const FrameOptions& options, FrameCounts* counts) {
    return impl_->draw(camera, dynamic, options, counts);
}

Status Renderer::draw_frame(const Camera& camera, const AssembledFrame& frame, const FrameOptions& options, FrameCounts* counts) {
    return impl_->draw_frame(camera, frame, options, counts);
}

Status Renderer::time_frames(const Camera& camera, int frames, const FrameOptions& options, FrameTimes* out) {
    Impl& r = *impl_;
    FrameTimes t;
    FrameOptions plain = options;
    plain.count_samples = false;
    r.gl.Finish();
    for (int i = 0; i < frames; ++i) {
        const double cpu0 = process_cpu_ms();
        const auto wall0 = std::chrono::steady_clock::now();
        if (Status s = r.draw(camera, {}, plain, nullptr); s != Status::ok) return s;
        r.gl.Finish();
        t.wall_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall0).count();
        t.cpu_ms += process_cpu_ms() - cpu0;
        ++t.frames;
    }
    if (Status s = r.draw(camera, {}, options, &t.counts); s != Status::ok) return s;
    if (out) *out = t;
    return Status::ok;
}

} // namespace depthcull::runtime
