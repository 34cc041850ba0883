// The compact binary meshes form (docs/mesh-format.md): everything the
// JSON holds, little-endian, vertex and index arrays ready to upload.
#include <algorithm>
#include <bit>
#include <cstring>

#include "depthcull/io.h"
#include "io/formats.h"
#include "io/mesh_common.h"

namespace depthcull::io {

namespace {

static_assert(std::endian::native == std::endian::little, "the binary mesh writer assumes a little-endian host");

// Little-endian values into a Sink; `at` counts every byte written, since
// the Sink's buffer is emptied as it streams (pad4 aligns to the file).
struct Out {
    Sink& sink;
    std::size_t at = 0;
    void raw(const void* data, std::size_t size) {
        sink.append(data, size);
        at += size;
    }
    template <class T>
    void put(const T& v) { raw(&v, sizeof v); }
    void str(const std::string& s) {
        put(std::uint32_t(s.size()));
        raw(s.data(), s.size());
    }
    void pad4() {
        while (at % 4) put('\0');
    }
};

void binary_document(Sink& sink, const MeshesDocument& document, const std::string& output_path) {
    const std::vector<SceneImage>& images = document.images;
    const SceneMeshes& meshes = document.meshes;
    const std::vector<Animation>& animations = document.animations;
    Out o{sink};
    o.raw("DCMESH\0\0", 8);
    o.put(std::uint32_t(1)); // format version
    // Bit 4: an insertion point section follows (only when there are
    // points, so other files are as before).
    // Bit 1: image entries carry a colour key (set only when one has one,
    // so files without keys stay as version 1 wrote them; a fill colour is
    // carried in the same word). Bit 2: made for linear filtering (clear:
    // nearest, as version 1 files were). Bit 3: an animation section
    // follows the draws (set only for animated scenes, so other files are
    // as before).
    const bool keys = std::any_of(images.begin(), images.end(), [](const SceneImage& img) { return img.has_trans || img.has_fill; });
    o.put(std::uint32_t((meshes.depth_test ? 1 : 0) | (keys ? 2 : 0) | (meshes.filter == Filter::linear ? 4 : 0) |
                         (animations.empty() ? 0 : kAnimationsFlag) | (meshes.insertion_points.empty() ? 0 : kInsertionPointsFlag)));
    o.put(meshes.viewport.x);
    o.put(meshes.viewport.y);
    o.put(std::int32_t(meshes.viewport.width));
    o.put(std::int32_t(meshes.viewport.height));
    o.put(std::uint32_t(images.size()));
    o.put(std::uint32_t(meshes.draws.size()));
    const SceneStats& st = meshes.stats;
    for (std::int64_t v : {st.elements, st.draw_calls, st.triangles, st.depth_levels, st.depth_bits, st.graph_edges}) o.put(v);
    o.put(document.seconds);
    for (const SceneImage& img : images) {
        o.str(img.id);
        o.str(output_relative_path(img.path, output_path));
        o.pad4();
        o.put(std::int32_t(img.width));
        o.put(std::int32_t(img.height));
        if (keys) o.put(std::uint32_t(img.has_fill ? kSolidFill | img.fill : img.has_trans ? kColorKeyed | img.trans : 0));
    }
    for (const Draw& d : meshes.draws) {
        o.put(std::uint32_t(d.image));
        o.put(std::uint8_t(d.pass == Pass::opaque ? 0 : 1));
        o.put(std::uint8_t(d.blend));
        o.put(std::uint16_t(0));
        o.put(std::uint32_t(d.vertex_count()));
        o.put(std::uint32_t(d.indices.size()));
        o.raw(d.vertices.data(), d.vertices.size() * sizeof(float));
        o.raw(d.indices.data(), d.indices.size() * sizeof(std::uint32_t));
    }
    if (!animations.empty()) {
        o.put(std::uint32_t(animations.size()));
        for (const Animation& a : animations) {
            o.put(std::uint32_t(a.frames.size()));
            for (const AnimationFrame& f : a.frames)
                for (std::int32_t v : {f.image, f.rect.x, f.rect.y, f.rect.w, f.rect.h, f.duration_ms}) o.put(v);
        }
        // Per draw its runs: grouped by draw (the writers and readers keep
        // them in draw order already; stable, so vertex order stays).
        std::vector<AnimatedRun> sorted = document.animated;
        std::stable_sort(sorted.begin(), sorted.end(), [](const AnimatedRun& a, const AnimatedRun& b) { return a.draw < b.draw; });
        std::size_t r = 0;
        for (std::size_t d = 0; d < meshes.draws.size(); ++d) {
            std::size_t end = r;
            while (end < sorted.size() && sorted[end].draw == d) ++end;
            o.put(std::uint32_t(end - r));
            for (; r < end; ++r)
                for (std::uint32_t v : {sorted[r].first_vertex, sorted[r].vertex_count, sorted[r].animation}) o.put(v);
        }
    }
    if (!meshes.insertion_points.empty()) {
        o.put(std::uint32_t(meshes.insertion_points.size()));
        for (const InsertionPoint& p : meshes.insertion_points) {
            o.put(std::uint64_t(p.element));
            o.put(std::int64_t(p.levels));
            o.put(std::int64_t(p.first_level));
            o.put(std::uint32_t(p.blend_draw));
            o.put(std::uint32_t(0)); // reserved
        }
    }
}

} // namespace

std::string meshes_to_binary(const MeshesDocument& document, const std::string& output_path) {
    return run_document(binary_document, nullptr, document, output_path);
}

void stream_meshes_binary(const WriteBytes& write, const MeshesDocument& document, const std::string& output_path) {
    run_document(binary_document, &write, document, output_path);
}

void write_meshes_binary(const std::string& path, const MeshesDocument& document) {
    write_file_atomic(path, [&](const WriteBytes& write) { stream_meshes_binary(write, document, path); });
}

} // namespace depthcull::io
