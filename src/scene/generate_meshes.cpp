// Paper 2.3 ReconstructScene and 2.3.3 GenerateMeshes: the element graph,
// the batching order, depth values, then meshes.
//
// Departures from the paper's GenerateMeshes, and why:
// - The opaque pass merges every element of one mesh key into one draw
//   regardless of order (the paper's closing remark): the depth test makes
//   the opaque pass order-independent. Draws go front to back.
// - Boundary polygons go to the blend pass in the sorted order, one draw
//   per run of elements sharing a mesh; only elements that blend take part.
#include <algorithm>
#include <numeric>

#include "scene/internal.h"

namespace depthcull::detail {

void MeshBuilder::add_polygon(Draw& d, std::uint32_t element, const Polygon& p, const std::vector<std::uint32_t>& triangles, float z) {
    if (capture_) {
        const auto base = std::uint32_t(capture_->points.size());
        capture_->points.insert(capture_->points.end(), p.begin(), p.end());
        for (std::uint32_t t : triangles) capture_->indices.push_back(base + t);
        return;
    }
    const Element& e = scene_.elements[element];
    const SceneImage& img = scene_.images[std::size_t(e.image)];
    note_element(d, element);
    const std::uint32_t base = std::uint32_t(d.vertex_count());
    const double iw = 1.0 / img.width, ih = 1.0 / img.height;
    for (const Vec2& v : p) {
        Vec2 s = apply(e.transform, {v.x - e.rect.x, v.y - e.rect.y});
        d.vertices.insert(d.vertices.end(), {float(s.x), float(s.y), z, float(v.x * iw), float(v.y * ih), e.color[0], e.color[1],
                                             e.color[2], e.color[3]});
    }
    for (std::uint32_t t : triangles) d.indices.push_back(base + t);
}

void MeshBuilder::add_boundary(Draw& d, std::uint32_t element, Shape shape, const ImageAnalysis* a, float z) {
    static const std::vector<std::uint32_t> quad{0, 1, 2, 0, 2, 3};
    const Blend blend = scene_.elements[element].blend;
    const ClippedPart* cut = nullptr;
    if (clipped_ && !capture_) {
        auto it = clipped_->blend.find(element);
        if (it != clipped_->blend.end()) cut = &it->second;
    }
    if (cut) // what is left after clip_hidden_parts; skirts around the original polygons as before
        for (std::size_t k = 0; k < cut->pieces.size(); ++k) add_polygon(d, element, cut->pieces[k], cut->triangles[k], z);
    if (shape == Shape::rect) {
        const Polygon rect = rect_polygon(scene_.elements[element].rect);
        if (!cut) add_polygon(d, element, rect, quad, z);
        // Blend opaque rects draw the same quad in every mode: no skirt.
        if (margin_ > 0 && blend != Blend::opaque) add_skirts(d, element, {rect}, z);
        return;
    }
    if (shape != Shape::analysis) return;
    for (const Polygon& p : a->boundary) {
        if (cut) break;
        auto it = triangulated_.find(&p);
        if (it == triangulated_.end()) it = triangulated_.emplace(&p, triangulate_polygon(p)).first;
        add_polygon(d, element, p, it->second, z);
    }
    if (blend == Blend::opaque) return;
    // A polygon with a coverage skirt gets no texel skirt: stacked, the
    // two overlap outside the polygon, and a pixel that snaps into both
    // while its texel lies inside the rect but past a texel skirt's clip
    // (or any pixel, once the rect test passes it) would blend twice.
    const std::vector<std::uint8_t> skirted = add_skirts(d, element, a->boundary, z);
    add_texel_skirts(d, element, a->boundary, z, &skirted);
}

void MeshBuilder::add_opaque(Draw& d, std::uint32_t element, Shape shape, const ImageAnalysis* a, float z) {
    static const std::vector<std::uint32_t> quad{0, 1, 2, 0, 2, 3};
    if (shape == Shape::rect) {
        if (merged_ && !capture_ && element < merged_->absorbed.size()) {
            if (merged_->absorbed[element]) return;
            auto it = merged_->quads.find(element);
            if (it != merged_->quads.end()) {
                add_polygon(d, element, it->second, quad, z);
                return;
            }
        }
        if (clipped_ && !capture_) {
            auto it = clipped_->opaque.find(element);
            if (it != clipped_->opaque.end()) {
                for (std::size_t k = 0; k < it->second.pieces.size(); ++k) add_polygon(d, element, it->second.pieces[k], it->second.triangles[k], z);
                return;
            }
        }
        add_polygon(d, element, rect_polygon(scene_.elements[element].rect), quad, z);
        return;
    }
    if (shape != Shape::analysis) return;
    // Opaque polygons are convex (paper 2.2: quadrilaterals; ours up to
    // kMaxOpaqueVertices), so a fan;
    // zero-area fan triangles (collinear vertices) are skipped, exactly.
    std::vector<std::uint32_t> fan;
    for (const Polygon& original : a->opaque) {
        const Polygon p = pull_inward(element, original);
        fan.clear();
        for (std::uint32_t k = 1; k + 1 < p.size(); ++k)
            if (orient(p[0], p[k], p[k + 1]) != 0) fan.insert(fan.end(), {0, k, k + 1});
        add_polygon(d, element, p, fan, z);
    }
}

void append_opaque_draws(const Scene& scene, const std::vector<std::uint32_t>& elements, const std::vector<std::int64_t>& levels,
                         const ElementShapes& shapes, const std::vector<const ImageAnalysis*>& analyses,
                         const std::vector<std::int32_t>& keys, std::int64_t denominator, MeshBuilder& builder,
                         std::vector<Draw>& draws) {
    std::vector<std::uint32_t> list;
    for (std::uint32_t e : elements)
        if (shapes.opaque[e] != Shape::none && keys[e] >= 0) list.push_back(e);
    if (list.empty()) return;
    // Nearest key first; within a key nearest element first. Sort on a
    // precomputed tuple per element: hash lookups in the comparator would
    // dominate for large scenes.
    std::unordered_map<std::int32_t, std::int64_t> nearest;
    for (std::uint32_t e : list) {
        auto [it, fresh] = nearest.emplace(keys[e], levels[e]);
        if (!fresh) it->second = std::max(it->second, levels[e]);
    }
    struct Item {
        std::int64_t key_front;
        std::int32_t key;
        std::int64_t level;
        std::uint32_t element;
    };
    std::vector<Item> items;
    items.reserve(list.size());
    for (std::uint32_t e : list) items.push_back({nearest[keys[e]], keys[e], levels[e], e});
    std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
        if (a.key_front != b.key_front) return a.key_front > b.key_front;
        if (a.key != b.key) return a.key < b.key;
        if (a.level != b.level) return a.level > b.level;
        return a.element > b.element;
    });
    for (std::size_t k = 0; k < items.size(); ++k) list[k] = items[k].element;
    std::vector<int> canon = canonical_images(scene);
    for (std::size_t k = 0; k < list.size(); ++k) {
        const std::uint32_t e = list[k];
        const Element& el = scene.elements[e];
        if (k == 0 || keys[e] != keys[list[k - 1]]) {
            Draw d;
            d.image = canon[std::size_t(el.image)];
            d.pass = Pass::opaque;
            d.blend = el.blend;
            draws.push_back(std::move(d));
        }
        builder.add_opaque(draws.back(), e, shapes.opaque[e], e < analyses.size() ? analyses[e] : nullptr,
                           depth_z(levels[e], true, denominator));
    }
}

void finish_stats(SceneMeshes& out) {
    out.stats.draw_calls = std::int64_t(out.draws.size());
    out.stats.triangles = 0;
    for (const Draw& d : out.draws) out.stats.triangles += std::int64_t(d.triangle_count());
}

namespace {

// The blend pass: runs of consecutive elements sharing a key, one draw each.
void append_blend_draws(const Scene& scene, const std::vector<std::uint32_t>& order, const std::vector<std::int64_t>* levels,
                        const std::vector<Shape>& boundary, const std::vector<const ImageAnalysis*>& analyses,
                        const std::vector<std::int32_t>& keys, std::int64_t denominator, MeshBuilder& builder,
                        std::vector<Draw>& draws) {
    const std::vector<int> canon = canonical_images(scene);
    std::int32_t last = -1;
    for (std::uint32_t e : order) {
        const Element& el = scene.elements[e];
        if (keys[e] != last) {
            Draw d;
            d.image = canon[std::size_t(el.image)];
            d.pass = Pass::blend;
            d.blend = el.blend;
            draws.push_back(std::move(d));
            last = keys[e];
        }
        float z = levels ? depth_z((*levels)[e], false, denominator) : 0.0f;
        builder.add_boundary(draws.back(), e, boundary[e], e < analyses.size() ? analyses[e] : nullptr, z);
    }
}

// assign_depth_levels with insertion points: the elements before a point
// keep their levels, the point reserves the next `levels` ones, and every
// element after it lies above them (as if in front of a sprite at every
// position), so its sprites fall between the two. Sets first_level.
std::vector<std::int64_t> assign_levels_with_points(const ElementGraph& graph, std::vector<InsertionPoint>& points) {
    std::vector<std::int64_t> level(graph.size(), 0);
    std::int64_t top = -1, floor = 0;
    std::size_t k = 0;
    auto open_points = [&](std::size_t i) {
        for (; k < points.size() && points[k].element == i; ++k) {
            points[k].first_level = std::max(floor, top + 1);
            floor = points[k].first_level + points[k].levels;
        }
    };
    for (std::size_t i = 0; i < graph.size(); ++i) {
        open_points(i);
        level[i] = floor;
        for (const std::uint32_t* b = graph.behind_begin(i); b != graph.behind_end(i); ++b)
            level[i] = std::max(level[i], level[*b] + 1);
        top = std::max(top, level[i]);
    }
    open_points(graph.size());
    return level;
}

// The blend-pass order sorted within each segment (elements between
// insertion points, segment_begin ascending): no element crosses a point.
std::vector<std::uint32_t> sort_segments(const ElementGraph& graph, const std::vector<std::int32_t>& keys, SortMethod method,
                                         const std::vector<std::size_t>& segment_begin) {
    std::vector<std::uint32_t> order;
    for (std::size_t s = 0; s < segment_begin.size(); ++s) {
        const std::size_t a = segment_begin[s], b = s + 1 < segment_begin.size() ? segment_begin[s + 1] : graph.size();
        if (a >= b) continue;
        ElementGraph sub;
        for (std::size_t i = a; i < b; ++i) {
            for (const std::uint32_t* t = graph.behind_begin(i); t != graph.behind_end(i); ++t)
                if (*t >= a) sub.targets.push_back(std::uint32_t(*t - a));
            sub.offsets.push_back(std::uint32_t(sub.targets.size()));
        }
        const std::vector<std::int32_t> sub_keys(keys.begin() + std::ptrdiff_t(a), keys.begin() + std::ptrdiff_t(b));
        for (std::uint32_t e : sort_order(sub, sub_keys, method)) order.push_back(std::uint32_t(e + a));
    }
    return order;
}

} // namespace

} // namespace depthcull::detail

namespace depthcull {

using namespace detail;

ReconstructStatus reconstruct_scene(const Scene& scene, const std::vector<const ImageAnalysis*>& analyses,
                                    const ReconstructOptions& options, SceneMeshes* out) {
    const std::size_t n = scene.elements.size();
    if (!out || analyses.size() != n || options.reserved_dynamic_levels < 0) return ReconstructStatus::invalid_scene;
    for (std::size_t i = 0; i < n; ++i) {
        const Element& e = scene.elements[i];
        if (!element_is_valid(scene, e)) return ReconstructStatus::invalid_scene;
        const SceneImage& img = scene.images[std::size_t(e.image)];
        if (img.width <= 0 || img.height <= 0 || !ImageView{nullptr, img.width, img.height, 0}.contains(e.rect))
            return ReconstructStatus::invalid_scene;
        if (!analyses[i] && e.blend != Blend::opaque && e.blend != Blend::multiply) return ReconstructStatus::invalid_scene;
    }

    // Paper 2.3 ReconstructScene: graph, sort, depth values, meshes.
    ElementShapes shapes = element_shapes(scene, analyses, options.opaque_polygons,
                                          options.texel_margin > 0 && !(options.coverage_margin > 0));
    if (options.cull_to_viewport) cull_to_viewport(scene, shapes);
    std::vector<std::int32_t> keys = mesh_keys(scene);
    // Without depth (ReconstructOptions::depthless) both passes follow
    // one painter's order, so every element that draws takes part in it.
    const bool depthless = options.depthless && depthless_possible(options);
    std::vector<std::int32_t> blend_keys = keys;
    std::vector<std::uint8_t> sorted(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (!shapes.blended[i] && !(depthless && shapes.opaque[i] != Shape::none)) blend_keys[i] = -1;
        sorted[i] = blend_keys[i] >= 0;
    }
    ElementGraph graph = build_graph(options.graph_memo, scene, analyses, shapes.boundary, options.graph, &sorted, options.graph_pair_budget);
    std::vector<InsertionPoint> points = options.insertion_points;
    for (std::size_t k = 0; k < points.size(); ++k)
        if (points[k].element > n || points[k].levels < 0 || points[k].levels > kMaxDepthLevels ||
            (k > 0 && points[k].element < points[k - 1].element))
            return ReconstructStatus::invalid_scene;
    std::vector<std::uint32_t> order;
    std::vector<std::int64_t> levels;
    // Segments between insertion points: [segment_begin[s], segment_begin[s + 1]).
    std::vector<std::size_t> segment_begin{0};
    if (points.empty()) {
        order = sort_order(graph, blend_keys, options.sort);
        levels = assign_depth_levels(graph);
    } else {
        levels = assign_levels_with_points(graph, points);
        for (const InsertionPoint& p : points) segment_begin.push_back(p.element);
        order = sort_segments(graph, blend_keys, options.sort, segment_begin);
    }
    segment_begin.push_back(n);

    std::int64_t depth_levels = 0;
    for (std::size_t i = 0; i < n; ++i)
        if (shapes.boundary[i] != Shape::none) depth_levels = std::max(depth_levels, levels[i] + 1);
    for (const InsertionPoint& p : points) depth_levels = std::max(depth_levels, p.first_level + p.levels);
    if (depth_levels + options.reserved_dynamic_levels > kMaxDepthLevels) return ReconstructStatus::too_many_depth_levels;
    const std::int64_t denominator = depth_denominator(depth_levels + options.reserved_dynamic_levels);

    SceneMeshes result;
    result.viewport = scene.viewport;
    result.depth_test = options.opaque_polygons && !depthless;
    result.filter = scene.filter;
    MeshBuilder builder(scene, 0, options.coverage_margin, options.texel_margin, options.element_spans);
    ClippedParts clipped;
    if (options.clip_hidden.enabled && options.opaque_polygons) {
        clipped = clip_hidden_parts(scene, analyses, shapes, levels, graph, keys, builder, options.clip_hidden);
        builder.set_clipped(&clipped);
    }
    std::vector<std::uint8_t> moved; // without depth: opaque polygons drawn in the blend pass
    if (depthless) moved = opaque_in_blend_pass(scene, analyses, shapes, graph, builder);
    MergedTiles merged;
    if (options.merge_opaque && options.opaque_polygons && !options.element_spans && !(options.coverage_margin > 0)) {
        merged = merge_opaque_tiles(scene, shapes, levels, keys, &clipped);
        if (depthless) keep_merged_in_order(graph, order, moved, merged);
        builder.set_merged(&merged);
    }
    if (depthless) { // no insertion points
        append_depthless_draws(scene, order, levels, denominator, shapes, analyses, keys, moved, builder, result.draws);
    } else {
        std::vector<std::uint32_t> all(n);
        std::iota(all.begin(), all.end(), 0u);
        append_opaque_draws(scene, all, levels, shapes, analyses, keys, denominator, builder, result.draws);
        if (points.empty()) {
            append_blend_draws(scene, order, &levels, shapes.boundary, analyses, keys, denominator, builder, result.draws);
        } else {
            // One run of blend draws per segment: no draw spans a point,
            // whose sprites' blend draws go between.
            std::vector<std::uint32_t> part;
            std::size_t at = 0;
            for (std::size_t s = 0; s + 1 < segment_begin.size(); ++s) {
                if (s > 0) points[s - 1].blend_draw = std::uint32_t(result.draws.size());
                part.clear();
                while (at < order.size() && order[at] < segment_begin[s + 1]) part.push_back(order[at++]);
                append_blend_draws(scene, part, &levels, shapes.boundary, analyses, keys, denominator, builder, result.draws);
            }
        }
    }
    result.depth_denominator = denominator;
    result.insertion_points = std::move(points);

    result.stats.elements = std::int64_t(n);
    result.stats.depth_levels = depth_levels;
    result.stats.graph_edges = std::int64_t(graph.edge_count());
    std::int64_t bits = 2;
    for (std::int64_t d = denominator; d > 1; d /= 2) ++bits;
    result.stats.depth_bits = bits;
    finish_stats(result);
    *out = std::move(result);
    return ReconstructStatus::ok;
}

namespace {

// Table 2 "Meshes only": every element draws its whole rect, blended, in
// the sorted order. The plan rectangle_meshes builds and rectangle_stats counts.
struct RectanglePlan {
    ElementShapes shapes;
    std::vector<std::int32_t> keys;
    std::vector<std::uint32_t> order;
    std::int64_t graph_edges = 0;
};

bool plan_rectangles(const Scene& scene, const ReconstructOptions& options, RectanglePlan& plan) {
    const std::size_t n = scene.elements.size();
    for (const Element& e : scene.elements)
        if (!element_is_valid(scene, e)) return false;
    plan.shapes.boundary.assign(n, Shape::rect);
    plan.shapes.opaque.assign(n, Shape::none);
    plan.shapes.blended.assign(n, 1);
    if (options.cull_to_viewport) cull_to_viewport(scene, plan.shapes);
    const std::vector<Shape>& rects = plan.shapes.boundary;
    std::vector<const ImageAnalysis*> none(n, nullptr);
    plan.keys = mesh_keys(scene);
    std::vector<std::uint8_t> sorted(n);
    for (std::size_t i = 0; i < n; ++i) {
        if (rects[i] == Shape::none) plan.keys[i] = -1;
        sorted[i] = plan.keys[i] >= 0;
    }
    ElementGraph graph = build_graph(scene, none, rects, GraphMode::boxes, &sorted, options.graph_pair_budget);
    plan.order = sort_order(graph, plan.keys, options.sort);
    plan.graph_edges = std::int64_t(graph.edge_count());
    return true;
}

} // namespace

ReconstructStatus reconstruct_scene(const Scene& scene, const SceneAnalysis& analysis, const ReconstructOptions& options,
                                    SceneMeshes* out) {
    if (analysis.of_element.size() != scene.elements.size()) return ReconstructStatus::invalid_scene;
    return reconstruct_scene(scene, analysis.per_element(), options, out);
}

ReconstructStatus rectangle_meshes(const Scene& scene, const ReconstructOptions& options, SceneMeshes* out) {
    const std::size_t n = scene.elements.size();
    RectanglePlan plan;
    if (!out || !plan_rectangles(scene, options, plan)) return ReconstructStatus::invalid_scene;
    SceneMeshes result;
    result.viewport = scene.viewport;
    result.depth_test = false;
    result.filter = scene.filter;
    MeshBuilder builder(scene, 0, options.coverage_margin, options.texel_margin, options.element_spans);
    std::vector<const ImageAnalysis*> none(n, nullptr);
    append_blend_draws(scene, plan.order, nullptr, plan.shapes.boundary, none, plan.keys, 0, builder, result.draws);
    result.stats.elements = std::int64_t(n);
    result.stats.graph_edges = plan.graph_edges;
    finish_stats(result);
    *out = std::move(result);
    return ReconstructStatus::ok;
}

ReconstructStatus rectangle_stats(const Scene& scene, const ReconstructOptions& options, SceneStats* out) {
    if (!out) return ReconstructStatus::invalid_scene;
    if (options.coverage_margin > 0) { // skirts: their triangles are counted by building them
        SceneMeshes meshes;
        const ReconstructStatus status = rectangle_meshes(scene, options, &meshes);
        if (status == ReconstructStatus::ok) *out = meshes.stats;
        return status;
    }
    RectanglePlan plan;
    if (!plan_rectangles(scene, options, plan)) return ReconstructStatus::invalid_scene;
    SceneStats stats;
    stats.elements = std::int64_t(scene.elements.size());
    stats.graph_edges = plan.graph_edges;
    stats.draw_calls = count_runs(plan.order, plan.keys);
    for (std::uint32_t e : plan.order)
        if (plan.keys[e] >= 0) stats.triangles += 2; // the rect's quad
    *out = stats;
    return ReconstructStatus::ok;
}

std::vector<TexelMap> element_maps(const Scene& scene) {
    std::vector<TexelMap> maps;
    maps.reserve(scene.elements.size());
    for (const Element& e : scene.elements) maps.push_back(texel_map(e));
    return maps;
}

SceneStats overpaint_stats(const Scene& scene) {
    SceneStats stats;
    stats.elements = std::int64_t(scene.elements.size());
    stats.draw_calls = stats.elements;    // one draw per element
    stats.triangles = 2 * stats.elements; // its rect's quad
    return stats;
}

} // namespace depthcull
