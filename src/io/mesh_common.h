// Internal to src/io: helpers shared by the mesh writers and readers.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "depthcull/io.h"
#include "depthcull/scene.h"

namespace depthcull::io {
// Binary image entries with flags bit 1: u32 colour key, this bit set when
// the image has one, 0xRRGGBB in the low bits.
inline constexpr std::uint32_t kColorKeyed = 1u << 24;
// ... or, with this bit instead, a solid-colour image (SceneImage::has_fill,
// 0xRRGGBB in the low bits; its path is empty).
inline constexpr std::uint32_t kSolidFill = 1u << 25;
// Binary header flags bit 3: an animation section follows the draws.
inline constexpr std::uint32_t kAnimationsFlag = 8;
// Binary header flags bit 4: an insertion point section follows the
// draws (and the animations).
inline constexpr std::uint32_t kInsertionPointsFlag = 16;
} // namespace depthcull::io

namespace depthcull::io {

// Output made in order (the mesh writers): appended to `bytes` and, when
// there is a writer, handed to it each time it passes kFlushBytes, so a
// streamed file never sits in memory whole (a 60,000-element scene's JSON
// is 125 MB); without one, `bytes` ends up the whole output.
class Sink {
public:
    static constexpr std::size_t kFlushBytes = std::size_t(1) << 20;
    explicit Sink(const WriteBytes* write = nullptr) : write_(write) {}
    std::string bytes;
    void flush_if_full() {
        if (write_ && bytes.size() >= kFlushBytes) flush();
    }
    void flush() {
        if (!write_ || bytes.empty()) return;
        (*write_)(bytes);
        bytes.clear();
    }
    // A block of raw bytes (a draw's vertices): a large one goes to the
    // writer as it is, not through a copy in `bytes`.
    void append(const void* data, std::size_t size) {
        if (write_ && size >= kFlushBytes) {
            flush();
            (*write_)(std::string_view(static_cast<const char*>(data), size));
            return;
        }
        bytes.append(static_cast<const char*>(data), size);
        flush_if_full();
    }

private:
    const WriteBytes* write_;
};

// A form's whole document into a Sink (mesh_json.cpp's json_document,
// mesh_binary.cpp's binary_document): images, meshes, paths relative to
// output_path, stats, then the animations and insertion points when there
// are some.
using DocumentWriter = void (*)(Sink&, const MeshesDocument& document, const std::string& output_path);

// Runs a form's writer whole (write null: the returned string) or streamed
// to `write` (the string comes back empty): each form's three public
// writers are this.
inline std::string run_document(DocumentWriter writer, const WriteBytes* write, const MeshesDocument& document, const std::string& output_path) {
    Sink sink(write);
    writer(sink, document, output_path);
    sink.flush();
    return std::move(sink.bytes);
}

// image_path (absolute or relative to the cwd) as the mesh and scene
// writers write it: relative to the directory of output_path (the cwd for
// stdout, which is what a reader of the stream resolves against), so the
// file finds its images wherever it is written, but absolute when the two
// share no directory below the root, since a path climbing to "/" and down
// again breaks as soon as either moves. A relative path written where the
// output's directory is the cwd (stdout, a bare file name) is kept as
// given: it names the image from there already. One rule for both
// writers: before, the mesh writers climbed through "/".
std::string output_relative_path(const std::string& image_path, const std::string& output_path);
const char* blend_name(Blend b);

// The readers' inverse of output_relative_path: a path as written in a
// meshes file, resolved against the file's directory (kept as written when
// base_dir is empty or the path is absolute or empty).
std::string resolve_mesh_path(const std::string& base_dir, const std::string& path);

// SceneMeshes::depth_denominator from the depth_bits a file states (the
// writers write 2 + log2 D): 0 when it names no usable mapping.
inline std::int64_t depth_denominator_from_bits(std::int64_t bits) {
    return bits >= 2 && bits <= 62 ? std::int64_t(1) << (bits - 2) : 0;
}

// Why float k of a draw's vertex array cannot be drawn, or nullptr: every
// value finite, z (the third of each vertex) in [0, 1] as the depth
// mapping writes it.
inline const char* vertex_float_problem(std::size_t k, float v) {
    if (!std::isfinite(v)) return "is not a finite number";
    if (k % kVertexFloats == 2 && !(v >= 0 && v <= 1)) return "is a depth (z) outside [0, 1]";
    return nullptr;
}

// Error unless the stated stats.depth_levels covers the levels the
// draws' z values use and fits the depth mapping (at most D / 2 levels,
// and kMaxDepthLevels): add_dynamic_elements puts new elements above them,
// and a file's word must not put them behind or overflow (issue 21).
inline void check_depth_levels(const SceneMeshes& m, const std::string& name) {
    const std::int64_t stated = m.stats.depth_levels, used = depth_levels_of_draws(m.draws, m.depth_denominator);
    const std::int64_t most = m.depth_denominator >= 2 ? std::min(kMaxDepthLevels, m.depth_denominator / 2) : kMaxDepthLevels;
    if (stated > most)
        throw Error(name + ": stats depth_levels " + std::to_string(stated) + " is more than the depth mapping resolves (" +
                    std::to_string(most) + " levels for depth_bits " + std::to_string(m.stats.depth_bits) + "; kMaxDepthLevels)");
    if (stated < used)
        throw Error(name + ": stats depth_levels " + std::to_string(stated) + " is lower than the " + std::to_string(used) +
                    " levels its draws' z values use");
}

// Why insertion point k of `m` (SceneMeshes::insertion_points, as a file
// states them) cannot be drawn at, or "" when it can; *field names the
// value at fault ("element", "levels", "first_level", "blend_draw").
// Checked against what the reader has already checked (stats, draws), so
// FrameAssembler::assemble_at and Renderer::draw_frame get points whose
// reserved levels lie inside the depth mapping, overlap neither another
// point's nor any static draw's depth, and whose blend draws go inside the
// static blend pass. Points 0..k-1 must have passed already (the readers
// check in order and stop at the first problem): the blend pass check
// leans on it.
inline std::string insertion_point_problem(const SceneMeshes& m, std::size_t k, const char** field) {
    const InsertionPoint& p = m.insertion_points[k];
    const InsertionPoint* prev = k ? &m.insertion_points[k - 1] : nullptr;
    auto text = [](std::int64_t v) { return std::to_string(v); };
    *field = "element";
    if (std::int64_t(p.element) > m.stats.elements || p.element > std::size_t(INT64_MAX))
        return "element " + std::to_string(p.element) + " is past the scene's " + text(m.stats.elements) + " elements (stats elements)";
    if (prev && p.element < prev->element) return "element " + std::to_string(p.element) + " is before the previous point's (points go in element order)";
    *field = "levels";
    if (p.levels < 0 || p.levels > kMaxDepthLevels) return "levels " + text(p.levels) + " is outside 0.." + text(kMaxDepthLevels);
    *field = "first_level";
    if (m.depth_denominator < 2) return "insertion points need depth values (stats depth_bits names no depth mapping)";
    if (p.first_level < 0 || p.first_level > m.stats.depth_levels - p.levels)
        return "levels " + text(p.first_level) + " + " + text(p.levels) + " are not inside the " + text(m.stats.depth_levels) +
               " depth levels of stats depth_levels";
    if (prev && p.first_level < prev->first_level + prev->levels) return "first_level " + text(p.first_level) + " overlaps the previous point's levels";
    *field = "blend_draw";
    if (p.blend_draw > m.draws.size()) return "blend_draw " + std::to_string(p.blend_draw) + " is past the " + std::to_string(m.draws.size()) + " draws";
    if (prev && p.blend_draw < prev->blend_draw) return "blend_draw " + std::to_string(p.blend_draw) + " is before the previous point's";
    // The previous point passed, so draws from its blend_draw on, which
    // hold this point's, are all blend draws: only the first point walks
    // them. Walking per point cost points x draws (65,536 points and
    // 131,072 draws, a 4 MB file, took 10 s).
    if (prev) return {};
    for (std::size_t d = p.blend_draw; d < m.draws.size(); ++d)
        if (m.draws[d].pass != Pass::blend)
            return "blend_draw " + std::to_string(p.blend_draw) + " is not in the blend pass (draw " + std::to_string(d) + " is opaque)";
    return {};
}

// Why the static draws' depths do not leave the points' reserved levels
// free (a vertex whose level lies in one), or "": sprites there would
// tie with static pixels in the depth test.
inline std::string insertion_levels_problem(const SceneMeshes& m) {
    if (m.insertion_points.empty() || m.depth_denominator < 2) return {};
    const double half = double(m.depth_denominator) / 2;
    for (std::size_t d = 0; d < m.draws.size(); ++d) {
        const std::vector<float>& v = m.draws[d].vertices;
        for (std::size_t k = 2; k < v.size(); k += kVertexFloats) {
            // Level k draws at (2k+1)/D and (2k+2)/D: k = ceil(z * D / 2) - 1.
            const std::int64_t level = std::int64_t(std::ceil(double(v[k]) * half)) - 1;
            // The points' ranges ascend (insertion_point_problem checked it).
            auto after = std::upper_bound(m.insertion_points.begin(), m.insertion_points.end(), level,
                                          [](std::int64_t l, const InsertionPoint& p) { return l < p.first_level; });
            if (after == m.insertion_points.begin()) continue;
            const InsertionPoint& p = *(after - 1);
            if (level < p.first_level + p.levels)
                return "draw " + std::to_string(d) + " vertex " + std::to_string(k / kVertexFloats) + " has depth level " +
                       std::to_string(level) + ", reserved by insertion point " +
                       std::to_string(std::size_t(after - 1 - m.insertion_points.begin()));
        }
    }
    return {};
}

} // namespace depthcull::io
