// depthcull: scenes, elements and their reconstruction into meshes
// (paper 2.3).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "depthcull/analyze.h"
#include "depthcull/geometry.h"
#include "depthcull/image.h"

namespace depthcull {

// How an element combines with what is behind it (OpenGL terms):
// alpha    src*a + dst*(1-a)         (the paper's case; may get opaque polygons)
// add      src*a + dst
// multiply src*dst                   (texel colour premultiplied by alpha in the shader)
// opaque   src                       (texel alpha ignored: the whole rect is opaque)
enum class Blend { alpha, add, multiply, opaque };

// The part of the world the frame shows: world [x, x+width) x [y, y+height)
// maps to framebuffer pixels [0, width) x [0, height), y down.
struct Viewport {
    double x = 0, y = 0;
    int width = 0, height = 0;
};

struct SceneImage {
    std::string id;
    std::string path;         // as loaded (absolute or relative to the cwd)
    int width = 0, height = 0;
};

// Paper 2: an element is an image (a rect of it) placed on screen.
struct Element {
    int image = 0;            // index into Scene::images
    Rect rect;                // source texels; always resolved (never empty in a valid scene)
    // SVG/canvas matrix [a b c d e f]: screen = (a*u + c*v + e, b*u + d*v + f),
    // (u, v) in texels of rect with its top-left at the origin.
    std::array<double, 6> transform{1, 0, 0, 1, 0, 0};
    std::array<float, 4> color{1, 1, 1, 1}; // multiplier, 0..1
    Blend blend = Blend::alpha;
};

// Elements in painter's order: elements[0] is farthest back.
struct Scene {
    Viewport viewport;
    Filter filter = Filter::nearest; // how the renderer samples textures
    std::vector<SceneImage> images;
    std::vector<Element> elements;
};

// Screen position of texel-space point p (relative to the rect's top-left).
inline Vec2 apply(const std::array<double, 6>& m, Vec2 p) {
    return {m[0] * p.x + m[2] * p.y + m[4], m[1] * p.x + m[3] * p.y + m[5]};
}

// ---- Meshes (paper 2.3.3)

enum class Pass {
    opaque, // depth test + write, blending off, drawn front to back
    blend,  // depth test (when the output has opaque draws), blending on, back to front
};

// Vertex layout: x, y (screen pixels), z (0..1, larger is nearer),
// u, v (0..1 of the whole image), r, g, b, a (colour multiplier).
inline constexpr int kVertexFloats = 9;

struct Draw {
    int image = 0;            // index into Scene::images
    Pass pass = Pass::blend;
    Blend blend = Blend::alpha;
    std::vector<float> vertices;        // kVertexFloats per vertex
    std::vector<std::uint32_t> indices; // triangles

    std::size_t vertex_count() const { return vertices.size() / kVertexFloats; }
    std::size_t triangle_count() const { return indices.size() / 3; }
};

// The analyzer of reconstruction. Best cases: draw_calls == number of
// distinct (image, blend) pairs; depth_levels == longest overlap chain.
struct SceneStats {
    std::int64_t elements = 0;
    std::int64_t draw_calls = 0;
    std::int64_t triangles = 0;
    std::int64_t depth_levels = 0;  // distinct element depth values used
    std::int64_t graph_edges = 0;
    double seconds = 0;
};

struct SceneMeshes {
    Viewport viewport;
    bool depth_test = false;  // false for overpaint and meshes-only output
    std::vector<Draw> draws;  // in the order to draw them
    SceneStats stats;
};

// ---- Reconstruction (paper 2.3)

enum class GraphMode {
    polygons, // elements overlap when their transformed boundary polygons do (default)
    boxes,    // when their transformed rects do (the paper's simple test; for comparison)
};

enum class SortMethod {
    none,  // keep painter's order
    paper, // SortElements of paper 2.3.1
    batch, // ours: topological order preferring the current mesh; the default
};

struct ReconstructOptions {
    GraphMode graph = GraphMode::polygons;
    SortMethod sort = SortMethod::batch;
    bool opaque_polygons = true; // false: no opaque pass at all
};

enum class ReconstructStatus {
    ok,
    invalid_scene,         // an element names a missing image or analysis, NaN transform, ...
    too_many_depth_levels, // more depth levels than a 24-bit depth buffer resolves
};

// Paper 2.3. analyses[i] is the per-image analysis of elements[i]'s rect
// (elements sharing an image rect may share one ImageAnalysis). On success
// `out` holds the draws in drawing order.
ReconstructStatus reconstruct_scene(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                                    const ReconstructOptions& options, SceneMeshes* out);

// Table 2 "Meshes only": 2.3's sorting and batching with every element's
// whole rect and no opaque polygons (no depth test).
ReconstructStatus rectangle_meshes(const Scene& scene, const ReconstructOptions& options, SceneMeshes* out);

// Overpaint (the unoptimized method, Table 2 "Unoptimized"): one draw per
// element, its whole rect as two triangles, in painter's order, no depth.
SceneMeshes overpaint_meshes(const Scene& scene);

} // namespace depthcull
