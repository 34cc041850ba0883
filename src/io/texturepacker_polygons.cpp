// Polygon export for TexturePacker atlases: our boundary polygons (paper
// 2.1) written into the fields TexturePacker itself uses for polygon
// sprites, so engines that already read them draw less transparent area
// with no code of ours:
//   "vertices":   [[x, y], ...] in the untrimmed sprite's coordinates
//   "verticesUV": [[x, y], ...] the same points in page texels
//   "triangles":  [[i, j, k], ...] indices into both lists
// A frame with several boundary polygons (disjoint parts) lists all their
// vertices and triangles together. Each polygon is ear-clipped
// (triangulate_polygon), not fanned: boundary polygons may be concave.
#include <atomic>
#include <cmath>

#include <nlohmann/json.hpp>

#include "depthcull/io.h"
#include "io/formats.h"

namespace depthcull::io {

namespace {

using Json = nlohmann::ordered_json;

Json number(double v) {
    if (v == 0) return 0;
    if (std::abs(v) < 9.0e15 && v == std::floor(v)) return std::int64_t(v);
    return v;
}

// Page texel point -> untrimmed sprite point (the inverse of the storage
// described in texturepacker.cpp).
Vec2 page_to_sprite(const AtlasFrame& f, Vec2 p) {
    double s = p.x - f.frame.x, t = p.y - f.frame.y;
    if (f.rotated) return {t + f.sprite_source.x, double(f.frame.w) - s + f.sprite_source.y};
    return {s + f.sprite_source.x, t + f.sprite_source.y};
}

void add_polygons(Json& out, const AtlasFrame& frame, const std::vector<Polygon>& polygons, AtlasPolygonStats& stats,
                  const std::string& where) {
    Json vertices = Json::array(), uv = Json::array(), triangles = Json::array();
    std::uint32_t base = 0;
    for (const Polygon& polygon : polygons) {
        std::vector<std::uint32_t> indices = triangulate_polygon(polygon);
        if (indices.empty() || indices.size() % 3 != 0) throw Error(where + ": a boundary polygon could not be triangulated");
        for (const Vec2& p : polygon) {
            Vec2 q = page_to_sprite(frame, p);
            vertices.push_back({number(q.x), number(q.y)});
            uv.push_back({number(p.x), number(p.y)});
        }
        for (std::size_t i = 0; i < indices.size(); i += 3)
            triangles.push_back({base + indices[i], base + indices[i + 1], base + indices[i + 2]});
        base += std::uint32_t(polygon.size());
        stats.vertices += std::int64_t(polygon.size());
        stats.triangles += std::int64_t(indices.size() / 3);
        stats.polygon_area += area(polygon);
    }
    out["vertices"] = std::move(vertices);
    out["verticesUV"] = std::move(uv);
    out["triangles"] = std::move(triangles);
}

std::string polygons_text(const std::string& path, const AtlasPolygonOptions& options, AtlasPolygonStats* stats_out,
                          AtlasAnalysis* analysis_out) {
    AtlasAnalysis local;
    AtlasAnalysis& result = analysis_out ? *analysis_out : local;
    result.atlas = load_texturepacker(path); // validates every frame
    const Atlas& atlas = result.atlas;
    result.page = load_image(atlas.image_path);
    const Image& page = result.page;
    if (atlas.width > 0 && (atlas.width != page.width || atlas.height != page.height))
        throw Error(path + ": meta.size " + std::to_string(atlas.width) + "x" + std::to_string(atlas.height) + " differs from " +
                    atlas.image_path + " (" + std::to_string(page.width) + "x" + std::to_string(page.height) + ")");
    for (const AtlasFrame& frame : atlas.frames)
        if (!page.view().contains(frame.frame))
            throw Error(path + ": frame '" + frame.name + "': texels lie outside the page " + atlas.image_path);
    // Frames in parallel, results by index: the text is the same for any
    // thread count.
    result.frames.assign(atlas.frames.size(), {});
    std::vector<std::uint8_t> hit(atlas.frames.size(), 0);
    std::atomic<std::size_t> done{0};
    parallel_for(atlas.frames.size(), options.threads, [&](std::size_t i) {
        bool from_cache = false;
        result.frames[i] = analyze_cached(page.view(), atlas.frames[i].frame, options.analyze, options.cache_dir, &from_cache);
        hit[i] = from_cache;
        if (options.progress) options.progress(++done, atlas.frames.size());
    });
    result.cache_hits = 0;
    for (std::uint8_t h : hit) result.cache_hits += h;

    Json doc = Json::parse(read_file(path));
    Json& frames = doc["frames"];
    AtlasPolygonStats stats;
    std::size_t index = 0;
    auto visit = [&](Json& f) {
        const AtlasFrame& frame = atlas.frames[index];
        add_polygons(f, frame, result.frames[index].boundary, stats, path + ": frame '" + frame.name + "'");
        ++index;
        stats.frames += 1;
        stats.frame_area += double(frame.frame.w) * frame.frame.h;
    };
    if (frames.is_object())
        for (auto& [name, f] : frames.items()) visit(f);
    else
        for (Json& f : frames) visit(f);
    if (stats_out) *stats_out = stats;
    return doc.dump(1, '\t') + "\n";
}

} // namespace

std::string atlas_with_polygons(const std::string& path, const AtlasPolygonOptions& options, AtlasPolygonStats* stats_out,
                                AtlasAnalysis* analysis) {
    return guarded(path, [&] { return polygons_text(path, options, stats_out, analysis); });
}

std::string atlas_with_polygons(const std::string& path, const AnalyzeOptions& options, AtlasPolygonStats* stats_out) {
    AtlasPolygonOptions o;
    o.analyze = options;
    return atlas_with_polygons(path, o, stats_out);
}

} // namespace depthcull::io
