// Reads the binary meshes form (docs/mesh-format.md) back into SceneMeshes,
// for games that load what the asset build wrote. Every count is checked
// against the bytes left before anything is allocated for it, so a file
// cannot make the reader allocate more than the file itself holds.
#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>

#include "depthcull/io.h"
#include "io/formats.h"
#include "io/mesh_common.h"

namespace depthcull::io {

namespace {

static_assert(std::endian::native == std::endian::little, "the binary mesh reader assumes a little-endian host");

// The fewest bytes an image entry (two empty strings, sizes) and a draw
// header take: what a count must leave room for.
constexpr std::size_t kMinImageBytes = 4 + 4 + 4 + 4;
constexpr std::size_t kDrawHeaderBytes = 4 + 1 + 1 + 2 + 4 + 4;

struct Reader {
    std::string_view bytes;
    const std::string& name;
    std::size_t pos = 0;

    [[noreturn]] void fail(std::size_t at, const std::string& what) const {
        throw Error(name + ": byte " + std::to_string(at) + ": " + what);
    }
    std::size_t left() const { return bytes.size() - pos; }
    void need(std::size_t n, const char* what) const {
        if (left() < n) fail(pos, std::string("the file ends inside ") + what);
    }
    template <class T>
    T get(const char* what) {
        need(sizeof(T), what);
        T v;
        std::memcpy(&v, bytes.data() + pos, sizeof v);
        pos += sizeof v;
        return v;
    }
    double finite_double(const char* what) {
        const std::size_t at = pos;
        const double v = get<double>(what);
        if (!std::isfinite(v)) fail(at, std::string(what) + " is not a finite number");
        return v;
    }
    std::int32_t size_value(const char* what, std::int32_t max) {
        const std::size_t at = pos;
        const auto v = get<std::int32_t>(what);
        if (v < 0 || v > max) fail(at, std::string(what) + " " + std::to_string(v) + " is outside 0.." + std::to_string(max));
        return v;
    }
    std::string str(const char* what) {
        const std::size_t at = pos;
        const auto n = get<std::uint32_t>(what);
        if (n > kMaxMeshStringBytes) fail(at, std::string(what) + " is longer than " + std::to_string(kMaxMeshStringBytes) + " bytes");
        need(n, what);
        std::string s(bytes.substr(pos, n));
        pos += n;
        return s;
    }
    void pad4(const char* what) {
        while (pos % 4) {
            if (get<char>(what) != 0) fail(pos - 1, std::string(what) + " padding is not zero");
        }
    }
};

void read_header(Reader& in, MeshesDocument& out, std::uint32_t* image_count, std::uint32_t* draw_count, bool* color_keys, bool* animations,
                 bool* points) {
    if (in.bytes.size() < 8 || !is_binary_meshes(in.bytes)) in.fail(0, "not a depthcull binary meshes file (no \"DCMESH\" magic)");
    in.pos = 8;
    const auto version = in.get<std::uint32_t>("the header");
    if (version != 1) in.fail(8, "format version " + std::to_string(version) + " is not supported (expected 1)");
    const auto flags = in.get<std::uint32_t>("the header");
    if (flags & ~31u)
        in.fail(12, "unknown flags " + std::to_string(flags) +
                        " (bit 0 depth_test, bit 1 colour keys, bit 2 linear filtering, bit 3 animations and bit 4 insertion points are defined)");
    *animations = flags & kAnimationsFlag;
    *points = flags & kInsertionPointsFlag;
    SceneMeshes& m = out.meshes;
    m.depth_test = flags & 1;
    m.filter = flags & 4 ? Filter::linear : Filter::nearest;
    *color_keys = flags & 2;
    m.viewport.x = in.finite_double("viewport x");
    m.viewport.y = in.finite_double("viewport y");
    m.viewport.width = in.size_value("viewport width", INT32_MAX);
    m.viewport.height = in.size_value("viewport height", INT32_MAX);
    const std::size_t counts_at = in.pos;
    *image_count = in.get<std::uint32_t>("the header");
    *draw_count = in.get<std::uint32_t>("the header");
    if (*image_count > kMaxMeshImages) in.fail(counts_at, "more than " + std::to_string(kMaxMeshImages) + " images");
    if (*draw_count > kMaxMeshDraws) in.fail(counts_at + 4, "more than " + std::to_string(kMaxMeshDraws) + " draws");
    for (std::int64_t* v : {&m.stats.elements, &m.stats.draw_calls, &m.stats.triangles, &m.stats.depth_levels, &m.stats.depth_bits,
                            &m.stats.graph_edges}) {
        const std::size_t at = in.pos;
        *v = in.get<std::int64_t>("the header");
        if (*v < 0) in.fail(at, "a negative stats count");
    }
    const std::size_t seconds_at = in.pos;
    out.seconds = in.finite_double("stats seconds");
    if (out.seconds < 0) in.fail(seconds_at, "negative stats seconds");
    m.depth_denominator = depth_denominator_from_bits(m.stats.depth_bits);
    if (in.left() / kMinImageBytes < *image_count || (in.left() - *image_count * kMinImageBytes) / kDrawHeaderBytes < *draw_count)
        in.fail(counts_at, std::to_string(*image_count) + " images and " + std::to_string(*draw_count) + " draws do not fit in the " +
                               std::to_string(in.left()) + " bytes left");
}

SceneImage read_image_entry(Reader& in, const std::string& base_dir, bool color_keys) {
    SceneImage img;
    img.id = in.str("an image id");
    img.path = resolve_mesh_path(base_dir, in.str("an image path"));
    in.pad4("an image entry");
    img.width = in.size_value("image width", kMaxImageSide);
    img.height = in.size_value("image height", kMaxImageSide);
    if (color_keys) {
        const std::size_t at = in.pos;
        const auto key = in.get<std::uint32_t>("an image colour key");
        // One encoding per value: a word with neither bit is 0.
        if ((key & ~(kColorKeyed | kSolidFill | 0xffffffu)) || ((key & kColorKeyed) && (key & kSolidFill)) ||
            (!(key & (kColorKeyed | kSolidFill)) && key))
            in.fail(at, "colour key " + std::to_string(key) + " has unknown bits");
        img.has_trans = key & kColorKeyed;
        img.has_fill = key & kSolidFill;
        if (img.has_fill) {
            if (!img.path.empty()) in.fail(at, "a solid fill image names a path");
            img.fill = key & 0xffffffu;
        }
        if (img.has_trans) img.trans = key & 0xffffffu;
    }
    return img;
}

Draw read_draw(Reader& in, std::size_t image_count, std::size_t* total_vertices, std::size_t* total_indices) {
    const std::size_t at = in.pos;
    Draw d;
    const auto image = in.get<std::uint32_t>("a draw header");
    if (image >= image_count) in.fail(at, "draw names image " + std::to_string(image) + " of " + std::to_string(image_count));
    d.image = int(image);
    const auto pass = in.get<std::uint8_t>("a draw header");
    if (pass > 1) in.fail(at + 4, "unknown pass " + std::to_string(pass) + " (0 opaque, 1 blend)");
    d.pass = pass == 0 ? Pass::opaque : Pass::blend;
    const auto blend = in.get<std::uint8_t>("a draw header");
    if (blend > 3) in.fail(at + 5, "unknown blend " + std::to_string(blend) + " (0 alpha, 1 add, 2 multiply, 3 opaque)");
    d.blend = Blend(blend);
    if (in.get<std::uint16_t>("a draw header") != 0) in.fail(at + 6, "reserved field is not 0");
    const auto vertex_count = in.get<std::uint32_t>("a draw header");
    const auto index_count = in.get<std::uint32_t>("a draw header");
    if (vertex_count > kMaxMeshVertices - *total_vertices)
        in.fail(at + 8, "more than " + std::to_string(kMaxMeshVertices) + " vertices in all draws");
    if (index_count > kMaxMeshIndices - *total_indices)
        in.fail(at + 12, "more than " + std::to_string(kMaxMeshIndices) + " indices in all draws");
    if (index_count % 3) in.fail(at + 12, "index count " + std::to_string(index_count) + " is not a multiple of 3 (triangles)");
    const std::uint64_t payload = std::uint64_t(vertex_count) * kVertexFloats * 4 + std::uint64_t(index_count) * 4;
    if (payload > in.left())
        in.fail(at + 8, std::to_string(vertex_count) + " vertices and " + std::to_string(index_count) + " indices do not fit in the " +
                            std::to_string(in.left()) + " bytes left");
    *total_vertices += vertex_count;
    *total_indices += index_count;

    const std::size_t vertices_at = in.pos;
    d.vertices.resize(std::size_t(vertex_count) * kVertexFloats);
    // Not for an empty draw: memcpy from or to the null data() of an empty
    // vector is undefined even for 0 bytes.
    if (!d.vertices.empty()) std::memcpy(d.vertices.data(), in.bytes.data() + in.pos, d.vertices.size() * 4);
    in.pos += d.vertices.size() * 4;
    for (std::size_t k = 0; k < d.vertices.size(); ++k)
        if (const char* problem = vertex_float_problem(k, d.vertices[k]))
            in.fail(vertices_at + 4 * k, "vertex " + std::to_string(k / kVertexFloats) + " value " + std::to_string(k % kVertexFloats) + " " + problem);
    const std::size_t indices_at = in.pos;
    d.indices.resize(index_count);
    if (!d.indices.empty()) std::memcpy(d.indices.data(), in.bytes.data() + in.pos, d.indices.size() * 4);
    in.pos += d.indices.size() * 4;
    for (std::size_t k = 0; k < d.indices.size(); ++k)
        if (d.indices[k] >= vertex_count)
            in.fail(indices_at + 4 * k, "index " + std::to_string(d.indices[k]) + " is not below the draw's vertex count " + std::to_string(vertex_count));
    return d;
}

// The animation section (flags bit 3): frames of one size naming existing
// images, then per draw its runs inside the draw's vertices naming existing
// animations.
void read_animations(Reader& in, MeshesDocument& out) {
    const std::size_t draws = out.meshes.draws.size();
    const std::size_t at = in.pos;
    const auto count = in.get<std::uint32_t>("the animation count");
    if (count == 0) in.fail(at, "flags bit 3 (animations) is set but the animation count is 0");
    if (count > kMaxMeshAnimations) in.fail(at, "more than " + std::to_string(kMaxMeshAnimations) + " animations");
    // Each animation holds at least a frame count and one frame; each draw a run count.
    constexpr std::size_t kFrameBytes = 6 * 4, kRunBytes = 3 * 4;
    if (in.left() / (4 + kFrameBytes) < count || (in.left() - count * (4 + kFrameBytes)) / 4 < draws)
        in.fail(at, std::to_string(count) + " animations and the runs of " + std::to_string(draws) + " draws do not fit in the " +
                        std::to_string(in.left()) + " bytes left");
    out.animations.reserve(count);
    for (std::uint32_t i = 0; i < count; ++i) {
        const std::size_t frames_at = in.pos;
        const auto frames = in.get<std::uint32_t>("an animation");
        if (frames == 0) in.fail(frames_at, "animation " + std::to_string(i) + " has no frames");
        if (frames > kMaxMeshAnimationFrames) in.fail(frames_at, "more than " + std::to_string(kMaxMeshAnimationFrames) + " frames in an animation");
        if (in.left() / kFrameBytes < frames)
            in.fail(frames_at, std::to_string(frames) + " frames do not fit in the " + std::to_string(in.left()) + " bytes left");
        Animation a;
        a.frames.reserve(frames);
        for (std::uint32_t k = 0; k < frames; ++k) {
            const std::size_t frame_at = in.pos;
            AnimationFrame f;
            const auto image = in.get<std::uint32_t>("an animation frame");
            if (image >= out.images.size()) in.fail(frame_at, "frame names image " + std::to_string(image) + " of " + std::to_string(out.images.size()));
            f.image = int(image);
            f.rect.x = in.size_value("frame x", kMaxImageSide);
            f.rect.y = in.size_value("frame y", kMaxImageSide);
            f.rect.w = in.size_value("frame width", kMaxImageSide);
            f.rect.h = in.size_value("frame height", kMaxImageSide);
            if (f.rect.empty()) in.fail(frame_at + 12, "an empty frame rect");
            if (k && (f.rect.w != a.frames[0].rect.w || f.rect.h != a.frames[0].rect.h))
                in.fail(frame_at + 12, "frame " + std::to_string(k) + " is not the size of frame 0");
            f.duration_ms = in.size_value("frame duration", INT32_MAX);
            a.frames.push_back(f);
        }
        out.animations.push_back(std::move(a));
    }
    for (std::size_t d = 0; d < draws; ++d) {
        const std::size_t runs_at = in.pos;
        const auto runs = in.get<std::uint32_t>("a draw's animated runs");
        // Room for the run counts of the draws after this one too.
        if (in.left() / kRunBytes < runs || in.left() - std::size_t(runs) * kRunBytes < (draws - d - 1) * 4)
            in.fail(runs_at, std::to_string(runs) + " animated runs of draw " + std::to_string(d) + " do not fit in the " +
                                 std::to_string(in.left()) + " bytes left");
        const std::uint64_t vertices = out.meshes.draws[d].vertex_count();
        for (std::uint32_t k = 0; k < runs; ++k) {
            const std::size_t run_at = in.pos;
            AnimatedRun r;
            r.draw = std::uint32_t(d);
            r.first_vertex = in.get<std::uint32_t>("an animated run");
            r.vertex_count = in.get<std::uint32_t>("an animated run");
            r.animation = in.get<std::uint32_t>("an animated run");
            if (r.vertex_count == 0 || std::uint64_t(r.first_vertex) + r.vertex_count > vertices)
                in.fail(run_at, "run of vertices " + std::to_string(r.first_vertex) + " + " + std::to_string(r.vertex_count) +
                                    " is not inside draw " + std::to_string(d) + "'s " + std::to_string(vertices));
            if (r.animation >= out.animations.size())
                in.fail(run_at + 8, "run names animation " + std::to_string(r.animation) + " of " + std::to_string(out.animations.size()));
            out.animated.push_back(r);
        }
    }
}

// The insertion point section (flags bit 4): a count, then per point u64
// element, i64 levels, i64 first_level, u32 blend_draw, u32 reserved 0;
// checked against the stats and draws read before.
void read_insertion_points(Reader& in, SceneMeshes& m) {
    const std::size_t at = in.pos;
    const auto count = in.get<std::uint32_t>("the insertion point count");
    if (count == 0) in.fail(at, "flags bit 4 (insertion points) is set but the insertion point count is 0");
    if (count > kMaxMeshInsertionPoints) in.fail(at, "more than " + std::to_string(kMaxMeshInsertionPoints) + " insertion points");
    constexpr std::size_t kPointBytes = 8 + 8 + 8 + 4 + 4;
    if (in.left() / kPointBytes < count)
        in.fail(at, std::to_string(count) + " insertion points do not fit in the " + std::to_string(in.left()) + " bytes left");
    m.insertion_points.reserve(count);
    for (std::uint32_t k = 0; k < count; ++k) {
        const std::size_t point_at = in.pos;
        InsertionPoint p;
        const auto element = in.get<std::uint64_t>("an insertion point");
        p.levels = in.get<std::int64_t>("an insertion point");
        p.first_level = in.get<std::int64_t>("an insertion point");
        p.blend_draw = in.get<std::uint32_t>("an insertion point");
        if (in.get<std::uint32_t>("an insertion point") != 0) in.fail(point_at + 28, "insertion point reserved field is not 0");
        if (element > std::uint64_t(INT64_MAX)) in.fail(point_at, "insertion point element " + std::to_string(element) + " is past the scene's elements");
        p.element = std::size_t(element);
        m.insertion_points.push_back(p);
        const char* field = "";
        if (std::string problem = insertion_point_problem(m, k, &field); !problem.empty()) {
            const std::size_t offset = std::string_view(field) == "element" ? 0 : std::string_view(field) == "levels" ? 8
                                       : std::string_view(field) == "first_level"                      ? 16 : 24;
            in.fail(point_at + offset, "insertion point " + std::to_string(k) + ": " + problem);
        }
    }
    if (std::string problem = insertion_levels_problem(m); !problem.empty()) in.fail(at, problem);
}

MeshesDocument read_binary(std::string_view bytes, const std::string& name, const std::string& base_dir) {
    Reader in{bytes, name};
    MeshesDocument out;
    std::uint32_t image_count = 0, draw_count = 0;
    bool color_keys = false, animations = false, points = false;
    read_header(in, out, &image_count, &draw_count, &color_keys, &animations, &points);
    out.images.reserve(image_count);
    for (std::uint32_t i = 0; i < image_count; ++i) out.images.push_back(read_image_entry(in, base_dir, color_keys));
    // Bit 1 is set exactly when some image has a key or a fill (the writer's rule).
    if (color_keys && std::none_of(out.images.begin(), out.images.end(), [](const SceneImage& img) { return img.has_trans || img.has_fill; }))
        in.fail(12, "flags bit 1 (colour keys) is set but no image has a colour key or fill");
    out.meshes.draws.reserve(draw_count);
    std::size_t total_vertices = 0, total_indices = 0;
    for (std::uint32_t i = 0; i < draw_count; ++i) out.meshes.draws.push_back(read_draw(in, image_count, &total_vertices, &total_indices));
    if (animations) read_animations(in, out);
    check_depth_levels(out.meshes, name);
    if (points) read_insertion_points(in, out.meshes);
    if (in.left())
        in.fail(in.pos, std::to_string(in.left()) + " bytes after the " + (points ? "insertion points" : animations ? "animations" : "last draw"));
    return out;
}

} // namespace

bool is_binary_meshes(std::string_view bytes) { return bytes.substr(0, 8) == std::string_view("DCMESH\0\0", 8); }

MeshesDocument meshes_from_binary(std::string_view bytes, const std::string& name, const std::string& base_dir) {
    return guarded(name, [&] { return read_binary(bytes, name, base_dir); });
}

MeshesDocument read_meshes(const std::string& path) {
    const std::string bytes = read_file(path);
    const std::string base = std::filesystem::path(path).parent_path().string();
    return is_binary_meshes(bytes) ? meshes_from_binary(bytes, path, base) : meshes_from_json(bytes, path, base);
}

} // namespace depthcull::io
