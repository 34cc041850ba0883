// The meshes JSON written by `depthcull optimize` (docs/mesh-format.md).
// Written by hand rather than through a JSON DOM: a 100k-element scene has
// millions of floats, and std::to_chars gives the shortest text that reads
// back as the same float, deterministically.
#include <charconv>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "depthcull/io.h"
#include "io/formats.h"
#include "io/mesh_common.h"

namespace depthcull::io {

namespace {

void append_float(std::string& s, float v) {
    char buf[32];
    if (v == 0) v = 0; // no "-0"
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    s.append(buf, r.ptr);
}

void append_double(std::string& s, double v) {
    char buf[32];
    if (v == 0) v = 0;
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    s.append(buf, r.ptr);
}

void append_int(std::string& s, std::int64_t v) {
    char buf[24];
    auto r = std::to_chars(buf, buf + sizeof buf, v);
    s.append(buf, r.ptr);
}

void append_string(std::string& s, const std::string& v) { s += nlohmann::json(v).dump(); }

// Animations (docs/mesh-format.md): the frames, and which vertex runs of
// which draws show an animated element, so an engine moves their UVs from
// frame 0's rect to the current frame's. After stats, before the document's "}".
void append_animations(Sink& sink, const std::vector<Animation>& animations, const std::vector<AnimatedRun>& runs) {
    std::string& a = sink.bytes;
    a += ",\n \"animations\": [";
    for (std::size_t i = 0; i < animations.size(); ++i) {
        a += i ? ",\n  {\"frames\": [" : "\n  {\"frames\": [";
        const auto& frames = animations[i].frames;
        for (std::size_t k = 0; k < frames.size(); ++k) {
            const AnimationFrame& f = frames[k];
            a += k ? ", " : "";
            a += "{\"image\": " + std::to_string(f.image) + ", \"rect\": [" + std::to_string(f.rect.x) + ", " + std::to_string(f.rect.y) + ", " +
                 std::to_string(f.rect.w) + ", " + std::to_string(f.rect.h) + "], \"duration\": " + std::to_string(f.duration_ms) + "}";
        }
        a += "]}";
        sink.flush_if_full();
    }
    a += "],\n \"animated\": [";
    for (std::size_t i = 0; i < runs.size(); ++i) {
        const AnimatedRun& r = runs[i];
        a += i ? ",\n  " : "\n  ";
        a += "{\"draw\": " + std::to_string(r.draw) + ", \"first_vertex\": " + std::to_string(r.first_vertex) + ", \"vertex_count\": " +
             std::to_string(r.vertex_count) + ", \"animation\": " + std::to_string(r.animation) + "}";
        sink.flush_if_full();
    }
    a += "]";
}

// The whole document into `sink` (flushed as it fills; the caller flushes
// the rest). Animations only when there are some, so other files are as
// they were before animations existed.
void json_document(Sink& sink, const MeshesDocument& document, const std::string& output_path) {
    const std::vector<SceneImage>& images = document.images;
    const SceneMeshes& meshes = document.meshes;
    std::string& s = sink.bytes;
    s += "{\"viewport\": {\"x\": ";
    append_double(s, meshes.viewport.x);
    s += ", \"y\": ";
    append_double(s, meshes.viewport.y);
    s += ", \"width\": ";
    append_int(s, meshes.viewport.width);
    s += ", \"height\": ";
    append_int(s, meshes.viewport.height);
    s += "},\n \"depth_test\": ";
    s += meshes.depth_test ? "true" : "false";
    s += ",\n \"filter\": ";
    s += meshes.filter == Filter::linear ? "\"linear\"" : "\"nearest\"";
    s += ",\n \"images\": [";
    for (std::size_t i = 0; i < images.size(); ++i) {
        const SceneImage& img = images[i];
        s += i ? ",\n  " : "\n  ";
        s += "{\"id\": ";
        check_utf8(img.id, output_name(output_path) + ": image id");
        append_string(s, img.id);
        s += ", \"path\": ";
        std::string path = img.has_fill ? std::string() : output_relative_path(img.path, output_path);
        check_utf8(path, output_name(output_path) + ": image \"" + img.id + "\": path");
        append_string(s, path);
        s += ", \"width\": ";
        append_int(s, img.width);
        s += ", \"height\": ";
        append_int(s, img.height);
        if (img.has_trans) {
            s += ", \"trans\": ";
            append_string(s, color_key_text(img.trans));
        }
        if (img.has_fill) {
            s += ", \"fill\": ";
            append_string(s, color_key_text(img.fill));
        }
        s += "}";
    }
    s += "],\n \"draws\": [";
    for (std::size_t d = 0; d < meshes.draws.size(); ++d) {
        const Draw& draw = meshes.draws[d];
        s += d ? ",\n  " : "\n  ";
        s += "{\"image\": ";
        append_string(s, images[std::size_t(draw.image)].id);
        s += ", \"pass\": ";
        s += draw.pass == Pass::opaque ? "\"opaque\"" : "\"blend\"";
        s += ", \"blend\": \"";
        s += blend_name(draw.blend);
        s += "\",\n   \"vertices\": [";
        for (std::size_t k = 0; k < draw.vertices.size(); ++k) {
            if (k % kVertexFloats == 0) {
                sink.flush_if_full();
                if (k) s += ", ";
            } else {
                s += ",";
            }
            append_float(s, draw.vertices[k]);
        }
        s += "],\n   \"indices\": [";
        for (std::size_t k = 0; k < draw.indices.size(); ++k) {
            if (k) s += ",";
            append_int(s, draw.indices[k]);
            sink.flush_if_full();
        }
        s += "]}";
        sink.flush_if_full();
    }
    const SceneStats& st = meshes.stats;
    s += "],\n \"stats\": {\"elements\": ";
    append_int(s, st.elements);
    s += ", \"draw_calls\": ";
    append_int(s, st.draw_calls);
    s += ", \"triangles\": ";
    append_int(s, st.triangles);
    s += ", \"depth_levels\": ";
    append_int(s, st.depth_levels);
    s += ", \"depth_bits\": ";
    append_int(s, st.depth_bits);
    s += ", \"graph_edges\": ";
    append_int(s, st.graph_edges);
    s += ", \"seconds\": ";
    append_double(s, document.seconds);
    s += "}";
    if (!document.animations.empty()) append_animations(sink, document.animations, document.animated);
    if (!meshes.insertion_points.empty()) {
        // Where moving sprites go (FrameAssembler::assemble_at); only when
        // there are some, so other files are as before.
        s += ",\n \"insertion_points\": [";
        for (std::size_t k = 0; k < meshes.insertion_points.size(); ++k) {
            const InsertionPoint& p = meshes.insertion_points[k];
            s += k ? ",\n  {\"element\": " : "\n  {\"element\": ";
            append_int(s, std::int64_t(p.element));
            s += ", \"levels\": ";
            append_int(s, p.levels);
            s += ", \"first_level\": ";
            append_int(s, p.first_level);
            s += ", \"blend_draw\": ";
            append_int(s, p.blend_draw);
            s += "}";
        }
        s += "]";
    }
    s += "}\n";
}

// The animated runs (depthcull::animated_runs), refused where an animated
// scene's meshes lack the element spans they are read from.
std::vector<AnimatedRun> checked_animated_runs(const Scene& scene, const SceneMeshes& meshes) {
    if (!scene.animations.empty())
        for (const Draw& draw : meshes.draws)
            if (draw.element_spans.empty() && draw.vertex_count() > 0)
                throw Error("meshes of an animated scene need their element spans (ReconstructOptions::element_spans)");
    return animated_runs(scene, meshes);
}

} // namespace

MeshesDocument meshes_document(const Scene& scene, SceneMeshes meshes) {
    MeshesDocument document;
    document.images = scene.images;
    document.animations = scene.animations;
    document.animated = checked_animated_runs(scene, meshes);
    document.meshes = std::move(meshes);
    return document;
}

std::string meshes_to_json(const MeshesDocument& document, const std::string& output_path) {
    return run_document(json_document, nullptr, document, output_path);
}

void stream_meshes_json(const WriteBytes& write, const MeshesDocument& document, const std::string& output_path) {
    run_document(json_document, &write, document, output_path);
}

void write_meshes_json(const std::string& path, const MeshesDocument& document) {
    write_file_atomic(path, [&](const WriteBytes& write) { stream_meshes_json(write, document, path); });
}

std::string output_relative_path(const std::string& image_path, const std::string& output_path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::path out_dir = output_path.empty() || output_path == "-" ? fs::path(".") : fs::path(output_path).parent_path();
    if (out_dir.empty()) out_dir = ".";
    const fs::path base = fs::absolute(out_dir, ec).lexically_normal();
    if (ec) return image_path;
    // A relative path already names the image from the cwd: written where
    // the cwd is the output's directory (stdout, a bare file name), it is
    // kept as given, so a meshes file read from memory (paths as written)
    // and written again is the same bytes ("a//b.png" is not normalized).
    if (fs::path(image_path).is_relative() && base == fs::absolute(".", ec).lexically_normal() && !ec) return image_path;
    const fs::path image = fs::absolute(image_path, ec).lexically_normal();
    if (ec) return image_path;
    auto a = image.begin(), b = base.begin();
    int shared = 0;
    while (a != image.end() && b != base.end() && *a == *b) ++a, ++b, ++shared;
    fs::path rel = image.lexically_relative(base);
    if (rel.empty() || shared < 2) return image.generic_string();
    return rel.generic_string();
}

std::string resolve_mesh_path(const std::string& base_dir, const std::string& path) {
    namespace fs = std::filesystem;
    if (base_dir.empty() || path.empty() || fs::path(path).is_absolute()) return path;
    return (fs::path(base_dir) / path).lexically_normal().generic_string();
}

const char* blend_name(Blend b) {
    switch (b) {
    case Blend::alpha: return "alpha";
    case Blend::add: return "add";
    case Blend::multiply: return "multiply";
    case Blend::opaque: return "opaque";
    }
    return "alpha";
}

} // namespace depthcull::io
