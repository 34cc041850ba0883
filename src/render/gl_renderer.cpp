// Draws a SceneMeshes the way a game would (paper 3): one draw call per
// Draw, opaque pass front to back with depth test and write and
// blending off, blended pass back to front. Overpaint, meshes-only and
// optimized output all go through the same programs and blend states, so
// the only thing that differs between them is which pixels get drawn.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>

#include "render/gl.h"
#include "runtime/shaders.h"

namespace depthcull::render {

namespace {

// Shared by every blend: world pixels to NDC without flipping y, so
// framebuffer row 0 (GL's bottom row) is the viewport's top row and
// glReadPixels returns the image top row first.
//
// Texel coordinates are not interpolated from the vertices' u, v: each
// triangle carries (flat) the affine map from window position to texel
// position and the fragment shader applies it to gl_FragCoord.
// Interpolating u, v in float over different triangles (an element's rect
// in overpaint, its polygons when optimized) differs in the last bits, and
// at every pixel centre that lies on a texel edge (any element placed on a
// half pixel or scaled by 1/2) that picks a different texel. The map is the
// element's own (element_maps(scene), from its transform), rounded
// to float once, so every triangle of an element in every mode carries
// bit-identical attributes and the shader computes the same texel position
// at each pixel: the texel a pixel shows does not depend on how its element
// was triangulated. Meshes without element maps get each triangle's map
// solved from its float vertices, which agree only to about 1e-4 texel.
const char* const kVertexShader = R"(
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec4 a_color;
layout(location = 2) in vec2 a_texel_origin;
layout(location = 3) in vec4 a_texel_axes;
layout(location = 4) in vec4 a_texel_rect;
uniform vec2 u_origin;
uniform vec2 u_scale;
flat out vec2 v_texel_origin;
flat out vec4 v_texel_axes;
flat out vec4 v_texel_rect;
out vec4 v_color;
void main() {
    gl_Position = vec4((a_position.xy - u_origin) * u_scale - 1.0, a_position.z * 2.0 - 1.0, 1.0);
    v_texel_origin = a_texel_origin;
    v_texel_axes = a_texel_axes;
    v_texel_rect = a_texel_rect;
    v_color = a_color;
}
)";

// No discard anywhere: it would switch off early depth rejection, the
// whole point of the opaque pass. Texels are not premultiplied (the blend
// tail, runtime/shaders.h, says what each Blend does with them). Nearest
// sampling fetches floor(texel position), as GL_NEAREST does.
//
// The rect test: a texel position outside the element's rect (x0, y0, x1,
// y1 in texels) outputs alpha 0, which every blend but opaque turns into
// "leave the pixel as it is". GL snaps vertices to its subpixel grid, so
// a pixel centre that close to a rect or polygon edge may be covered in
// one mode and not in another; with the test, and boundary polygons grown
// by a skirt (ReconstructOptions::coverage_margin), such a pixel draws only
// when its texel is inside the rect, in every mode, and otherwise adds a
// fragment that changes nothing. Blend opaque elements draw the same rect
// quad in every mode (so the same coverage) and keep no test: with
// blending off alpha 0 would not be a no-op.
const char* const kFragmentShader = R"(
uniform sampler2D u_texture;
uniform int u_nearest;
flat in vec2 v_texel_origin;
flat in vec4 v_texel_axes;
flat in vec4 v_texel_rect;
in vec4 v_color;
out vec4 o_color;
void main() {
    vec2 t = v_texel_origin + v_texel_axes.xy * gl_FragCoord.x + v_texel_axes.zw * gl_FragCoord.y;
    vec2 size = vec2(textureSize(u_texture, 0));
    vec4 texel;
    vec2 cell;
    if (u_nearest != 0) {
        // A centre exactly on a texel edge takes the texel on the side the
        // fill rule gives the pixel to (towards +x, then +y in window
        // space), so the texel a polygon's edge pixel shows lies inside that
        // polygon. floor() alone picks the wrong side whenever the texel axis
        // runs against the window axis (a mirrored or rotated element placed
        // on a half pixel), and the opaque pass would then write a
        // non-opaque texel. The shared element map does not make this
        // redundant: it makes overpaint and the optimized meshes pick the
        // same texel, but the opaque pass must also pick one its polygon
        // covers, and exact ties are common (polygon edges lie on texel
        // edges, and half-pixel placements put pixel centres on them).
        vec2 along = vec2(v_texel_axes.x != 0.0 ? v_texel_axes.x : v_texel_axes.z,
                          v_texel_axes.y != 0.0 ? v_texel_axes.y : v_texel_axes.w);
        vec2 texel_index = floor(t) - vec2(equal(t, floor(t))) * vec2(lessThan(along, vec2(0.0)));
        texel = texelFetch(u_texture, ivec2(clamp(texel_index, vec2(0.0), size - 1.0)), 0);
        cell = texel_index;
    } else {
        texel = texture(u_texture, t / size);
        cell = floor(t);
    }
    vec4 c = texel * v_color;
#if !defined(BLEND_OPAQUE)
    if (any(lessThan(cell, v_texel_rect.xy)) || any(greaterThanEqual(cell, v_texel_rect.zw))) c = vec4(0.0);
#endif
)"; // runtime's kBlendTail ends it, as it ends the runtime's shader

// Per GL vertex: position (3), colour (4), texel map origin (2), axes (4)
// and rect (4).
constexpr int kGlVertexFloats = 17;

using runtime::kBlendCount;

} // namespace

struct GlRenderer::Impl {
    // The context and the framebuffer (RGBA8 + DEPTH_COMPONENT24, read
    // back row 0 first) are a GlHost's; the GL functions, blend states and
    // shader tail runtime's. Declared first, so destroyed last.
    std::unique_ptr<GlHost> host;
    runtime::GlFunctions gl;
    GLuint programs[kBlendCount] = {};
    GLint origin_location[kBlendCount] = {}, scale_location[kBlendCount] = {}, nearest_location[kBlendCount] = {};
    GLuint query = 0;
    std::vector<GLuint> textures;
    std::vector<std::pair<int, int>> texture_sizes;
    bool nearest = true;
    int width = 0, height = 0;

    struct Batch {
        int image;
        Pass pass;
        Blend blend;
        std::size_t first_vertex, vertex_count;
    };
    // One uploaded SceneMeshes: its own vertex buffer and vertex array.
    struct MeshSet {
        GLuint vao = 0, vertex_buffer = 0;
        std::vector<Batch> batches;
        bool depth_test = false;
        Viewport viewport;
        std::int64_t triangles = 0, draw_calls = 0;
    };
    std::vector<MeshSet> sets;
    std::size_t current = 0;
    const MeshSet& set() const {
        static const MeshSet none;
        return current < sets.size() ? sets[current] : none;
    }

    // EGL contexts are current per thread; several renderers on one thread
    // (tests compare platforms) each make theirs current before GL calls.
    void make_current() { host->make_current(); }

    void clear_sets() {
        for (MeshSet& m : sets) {
            gl.DeleteBuffers(1, &m.vertex_buffer);
            gl.DeleteVertexArrays(1, &m.vao);
        }
        sets.clear();
        current = 0;
    }

    ~Impl() {
        if (host && gl.DeleteProgram) {
            make_current();
            for (GLuint p : programs) gl.DeleteProgram(p);
            gl.DeleteTextures(GLsizei(textures.size()), textures.data());
            clear_sets();
            gl.DeleteQueries(1, &query);
        }
    }

    std::string build_programs() {
        if (std::string why = runtime::build_blend_programs(gl, runtime::kDesktopHeader, kVertexShader, kFragmentShader, programs);
            !why.empty())
            return "GL " + why;
        for (int b = 0; b < kBlendCount; ++b) {
            origin_location[b] = gl.GetUniformLocation(programs[b], "u_origin");
            scale_location[b] = gl.GetUniformLocation(programs[b], "u_scale");
            nearest_location[b] = gl.GetUniformLocation(programs[b], "u_nearest");
        }
        return {};
    }

    void resize(int w, int h) {
        host->bind_framebuffer(w, h); // throws past the GL's limits
        width = w;
        height = h;
    }

    void draw_frame() {
        const MeshSet& m = set();
        if (width > 0) host->bind_framebuffer(width, height);
        gl.Viewport(0, 0, width, height);
        gl.ClearColor(0, 0, 0, 0);
        // Overpaint needs no depth buffer, so it does not pay for clearing one.
        if (m.depth_test) {
            gl.DepthMask(GL_TRUE);
            if (gl.ClearDepth) gl.ClearDepth(0.0);
            else gl.ClearDepthf(0.0f);
            gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            gl.Enable(GL_DEPTH_TEST);
            gl.DepthFunc(GL_GREATER); // larger z is nearer (scene.h)
        } else {
            gl.Clear(GL_COLOR_BUFFER_BIT);
            gl.Disable(GL_DEPTH_TEST);
        }
        if (m.batches.empty()) return;
        const Viewport& viewport = m.viewport;
        gl.BindVertexArray(m.vao);
        gl.ActiveTexture(GL_TEXTURE0);
        int bound_program = -1, bound_image = -1;
        for (const Batch& b : m.batches) {
            int program = int(b.blend);
            if (program != bound_program) {
                gl.UseProgram(programs[program]);
                gl.Uniform2f(origin_location[program], float(viewport.x), float(viewport.y));
                gl.Uniform2f(scale_location[program], 2.0f / float(width), 2.0f / float(height));
                gl.Uniform1i(nearest_location[program], nearest ? 1 : 0);
                bound_program = program;
            }
            if (b.image != bound_image) {
                gl.BindTexture(GL_TEXTURE_2D, textures[std::size_t(b.image)]);
                bound_image = b.image;
            }
            runtime::set_blend_state(gl, b.pass, b.blend, m.depth_test);
            gl.DrawArrays(GL_TRIANGLES, GLint(b.first_vertex), GLsizei(b.vertex_count));
        }
    }
};

GlRenderer::GlRenderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
GlRenderer::~GlRenderer() = default;

std::unique_ptr<GlRenderer> GlRenderer::create(const GlOptions& options) {
    auto impl = std::make_unique<Impl>();
    impl->host = GlHost::create(options, GlApi::desktop); // NoContext when it fails
    runtime::GlFunctions& gl = impl->gl;
    std::string missing = gl.load(&GlHost::get_proc_address, true);
    if (missing.empty() && !gl.GetQueryObjectui64v) missing = "glGetQueryObjectui64v"; // draw_counted's
    if (!missing.empty()) {
        gl.DeleteProgram = nullptr; // nothing was created
        throw NoContext("no OpenGL context: " + impl->host->description() + ": GL lacks " + missing);
    }
    if (std::string why = impl->build_programs(); !why.empty()) throw Error("no usable OpenGL: " + why);
    gl.GenQueries(1, &impl->query);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    return std::unique_ptr<GlRenderer>(new GlRenderer(std::move(impl)));
}

const std::string& GlRenderer::description() const { return impl_->host->description(); }
bool GlRenderer::is_software() const { return impl_->host->is_software(); }

void GlRenderer::set_images(const std::vector<ImageView>& images, Filter filter) {
    impl_->make_current();
    Impl& r = *impl_;
    runtime::GlFunctions& gl = r.gl;
    gl.DeleteTextures(GLsizei(r.textures.size()), r.textures.data());
    r.textures.assign(images.size(), 0);
    r.texture_sizes.clear();
    r.nearest = filter == Filter::nearest;
    gl.GenTextures(GLsizei(r.textures.size()), r.textures.data());
    GLint max_size = 0;
    gl.GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    const GLint mode = filter == Filter::linear ? GL_LINEAR : GL_NEAREST;
    for (std::size_t i = 0; i < images.size(); ++i) {
        const ImageView& v = images[i];
        if (v.width <= 0 || v.height <= 0 || v.width > max_size || v.height > max_size)
            throw Error("image " + std::to_string(i) + " (" + std::to_string(v.width) + "x" + std::to_string(v.height) +
                        ") is outside this GL's texture limit " + std::to_string(max_size));
        gl.BindTexture(GL_TEXTURE_2D, r.textures[i]);
        r.texture_sizes.emplace_back(v.width, v.height);
        gl.PixelStorei(GL_UNPACK_ROW_LENGTH, GLint(v.stride / 4));
        gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, v.width, v.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, v.rgba);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, mode);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, mode);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    gl.PixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR) throw Error("GL error " + std::to_string(e) + " uploading textures");
}

namespace {

// A triangle's window-to-texel map as the vertex shader takes it: origin
// (u, v at window (0, 0)), then d(u, v)/dx, then d(u, v)/dy, then the rect
// (x0, y0, x1, y1) outside which it draws nothing.
using GlTexelMap = std::array<float, 10>;

// Meshes without element maps do not say which rect a triangle belongs
// to: no rect test for them.
constexpr float kNoRect = 1e30f;

// An element's exact map (element_maps(scene), screen pixels) moved
// to window coordinates and rounded to float once, so every triangle of the
// element, in every mode, hands the shader bit-identical attributes and the
// shader computes the same texel position at each pixel.
GlTexelMap element_gl_map(const TexelMap& t, const Viewport& vp) {
    return {float(t.u0 + t.ux * vp.x + t.uy * vp.y),
            float(t.v0 + t.vx * vp.x + t.vy * vp.y),
            float(t.ux),
            float(t.vx),
            float(t.uy),
            float(t.vy),
            float(t.rect.x),
            float(t.rect.y),
            float(double(t.rect.x) + t.rect.w),
            float(double(t.rect.y) + t.rect.h)};
}

// For meshes without element maps (read from a file): the map of triangle
// `corner` of `d` itself, solved in double from its float vertices.
// Triangulations of one element agree only up to the float rounding of
// their vertices, so a pixel centre within about 1e-4 texel of a texel edge
// may show different texels in different meshes. Returns false for a
// triangle with no area, which GL would not draw either.
bool triangle_gl_map(const Draw& d, const std::uint32_t (&corner)[3], const Viewport& vp, int image_w, int image_h,
                     GlTexelMap& map) {
    double X[3][2], T[3][2];
    for (int k = 0; k < 3; ++k) {
        const float* v = &d.vertices[std::size_t(corner[k]) * kVertexFloats];
        X[k][0] = double(v[0]) - vp.x;
        X[k][1] = double(v[1]) - vp.y;
        // Polygon corners sit on the texel grid (geometry.h); undo the float
        // rounding of u = texel / width so every triangle of an element
        // derives its map from the same exact corners.
        T[k][0] = std::round(double(v[3]) * image_w * 256.0) / 256.0;
        T[k][1] = std::round(double(v[4]) * image_h * 256.0) / 256.0;
    }
    const double dx1 = X[1][0] - X[0][0], dy1 = X[1][1] - X[0][1];
    const double dx2 = X[2][0] - X[0][0], dy2 = X[2][1] - X[0][1];
    const double det = dx1 * dy2 - dy1 * dx2;
    if (!(det != 0) || !std::isfinite(det)) return false;
    double axis_x[2], axis_y[2], origin[2];
    for (int c = 0; c < 2; ++c) {
        const double dt1 = T[1][c] - T[0][c], dt2 = T[2][c] - T[0][c];
        axis_x[c] = (dt1 * dy2 - dt2 * dy1) / det;
        axis_y[c] = (dt2 * dx1 - dt1 * dx2) / det;
        origin[c] = T[0][c] - axis_x[c] * X[0][0] - axis_y[c] * X[0][1];
    }
    map = {float(origin[0]), float(origin[1]), float(axis_x[0]), float(axis_x[1]), float(axis_y[0]), float(axis_y[1]),
           -kNoRect, -kNoRect, kNoRect, kNoRect};
    return true;
}

// True when GL draws nothing for the triangle: no area in double, as GL
// would see its float vertices (up to its own snapping).
bool degenerate(const Draw& d, const std::uint32_t (&corner)[3]) {
    const float* a = &d.vertices[std::size_t(corner[0]) * kVertexFloats];
    const float* b = &d.vertices[std::size_t(corner[1]) * kVertexFloats];
    const float* c = &d.vertices[std::size_t(corner[2]) * kVertexFloats];
    const double det = (double(b[0]) - a[0]) * (double(c[1]) - a[1]) - (double(b[1]) - a[1]) * (double(c[0]) - a[0]);
    return !(det != 0) || !std::isfinite(det);
}

// Appends triangle `corner` of `d` as three GL vertices carrying `map`
// (see kVertexShader).
void append_triangle(const Draw& d, const std::uint32_t (&corner)[3], const GlTexelMap& map, std::vector<float>& out) {
    for (int k = 0; k < 3; ++k) {
        const float* v = &d.vertices[std::size_t(corner[k]) * kVertexFloats];
        out.insert(out.end(), {v[0], v[1], v[2], v[5], v[6], v[7], v[8]});
        out.insert(out.end(), map.begin(), map.end());
    }
}

} // namespace

void GlRenderer::set_meshes(const SceneMeshes& meshes, const std::vector<TexelMap>& maps) {
    impl_->make_current();
    impl_->clear_sets();
    select_meshes(add_meshes(meshes, maps));
}

namespace {

// Per vertex, the element its span names (~0u where none does).
void vertex_elements(const Draw& d, std::vector<std::uint32_t>& out) {
    out.assign(d.vertex_count(), ~0u);
    for (std::size_t k = 0; k < d.element_spans.size(); ++k) {
        const std::size_t end = k + 1 < d.element_spans.size() ? d.element_spans[k + 1].first_vertex : out.size();
        for (std::size_t v = d.element_spans[k].first_vertex; v < std::min(end, out.size()); ++v) out[v] = d.element_spans[k].element;
    }
}

} // namespace

int GlRenderer::add_meshes(const SceneMeshes& meshes, const std::vector<TexelMap>& maps) {
    impl_->make_current();
    Impl& r = *impl_;
    runtime::GlFunctions& gl = r.gl;
    Impl::MeshSet m;
    m.viewport = meshes.viewport;
    m.depth_test = meshes.depth_test;
    std::vector<float> vertices;
    std::vector<GlTexelMap> element_maps;
    element_maps.reserve(maps.size());
    for (const TexelMap& t : maps) element_maps.push_back(element_gl_map(t, m.viewport));
    std::vector<std::uint32_t> elements;
    for (const Draw& d : meshes.draws) {
        if (d.image < 0 || std::size_t(d.image) >= r.textures.size())
            throw Error("draw names image " + std::to_string(d.image) + " but " + std::to_string(r.textures.size()) +
                        " images are loaded");
        const auto [image_w, image_h] = r.texture_sizes[std::size_t(d.image)];
        const std::size_t first = vertices.size() / kGlVertexFloats;
        vertex_elements(d, elements);
        for (std::size_t t = 0; t + 3 <= d.indices.size(); t += 3) {
            const std::uint32_t corner[3] = {d.indices[t], d.indices[t + 1], d.indices[t + 2]};
            for (std::uint32_t i : corner)
                if (i >= d.vertex_count()) throw Error("draw has index " + std::to_string(i) + " past its vertices");
            GlTexelMap map;
            // The element's own map when the triangle names one (all three
            // corners alike); else the triangle's.
            const std::uint32_t element = elements[corner[0]];
            if (element < element_maps.size() && elements[corner[1]] == element && elements[corner[2]] == element) {
                if (degenerate(d, corner)) continue;
                map = element_maps[element];
            } else if (!triangle_gl_map(d, corner, m.viewport, image_w, image_h, map)) {
                continue;
            }
            append_triangle(d, corner, map, vertices);
        }
        // Counted as the scene draws them, degenerate triangles included.
        if (d.triangle_count() == 0) continue;
        m.triangles += std::int64_t(d.triangle_count());
        ++m.draw_calls;
        const std::size_t count = vertices.size() / kGlVertexFloats - first;
        if (count) m.batches.push_back({d.image, d.pass, d.blend, first, count});
    }
    gl.GenVertexArrays(1, &m.vao);
    gl.GenBuffers(1, &m.vertex_buffer);
    gl.BindVertexArray(m.vao);
    gl.BindBuffer(GL_ARRAY_BUFFER, m.vertex_buffer);
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data(), GL_STATIC_DRAW);
    const GLsizei stride = kGlVertexFloats * sizeof(float);
    const int sizes[5] = {3, 4, 2, 4, 4};
    for (GLuint i = 0, offset = 0; i < 5; offset += GLuint(sizes[i]), ++i) {
        gl.VertexAttribPointer(i, sizes[i], GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(std::uintptr_t(offset * sizeof(float))));
        gl.EnableVertexAttribArray(i);
    }
    r.sets.push_back(std::move(m));
    if (GLenum e = gl.GetError(); e != GL_NO_ERROR) throw Error("GL error " + std::to_string(e) + " uploading meshes");
    return int(r.sets.size()) - 1;
}

void GlRenderer::select_meshes(int slot) {
    impl_->make_current();
    Impl& r = *impl_;
    if (slot < 0 || std::size_t(slot) >= r.sets.size()) throw Error("no meshes uploaded in slot " + std::to_string(slot));
    r.current = std::size_t(slot);
    r.resize(r.sets[r.current].viewport.width, r.sets[r.current].viewport.height);
}

double GlRenderer::time_frame() {
    impl_->make_current();
    Impl& r = *impl_;
    auto start = std::chrono::steady_clock::now();
    r.draw_frame();
    r.gl.Finish();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

void GlRenderer::draw() {
    impl_->make_current();
    impl_->draw_frame();
}

FrameCounts GlRenderer::draw_counted() {
    impl_->make_current();
    Impl& r = *impl_;
    r.gl.BeginQuery(GL_SAMPLES_PASSED, r.query);
    r.draw_frame();
    r.gl.EndQuery(GL_SAMPLES_PASSED);
    GLuint64 samples = 0;
    r.gl.GetQueryObjectui64v(r.query, GL_QUERY_RESULT, &samples);
    return {r.set().draw_calls, r.set().triangles, std::int64_t(samples)};
}

Image GlRenderer::read_pixels() { return impl_->host->read_pixels(); }

std::vector<double> GlRenderer::time_frames(int frames, int warmup) {
    impl_->make_current();
    Impl& r = *impl_;
    for (int i = 0; i < warmup; ++i) r.draw_frame();
    r.gl.Finish();
    std::vector<double> ms;
    ms.reserve(std::size_t(std::max(frames, 0)));
    for (int i = 0; i < frames; ++i) ms.push_back(time_frame());
    return ms;
}

} // namespace depthcull::render
