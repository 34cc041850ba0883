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

std::string polygons_json(const std::string& path, const Atlas& atlas, const std::vector<ImageAnalysis>& frame_analyses,
                          AtlasPolygonStats* stats_out) {
    if (frame_analyses.size() != atlas.frames.size())
        throw Error(path + ": " + std::to_string(frame_analyses.size()) + " frame analyses for " + std::to_string(atlas.frames.size()) +
                    " frames");
    Json doc = Json::parse(read_file(path));
    Json& frames = doc["frames"];
    AtlasPolygonStats stats;
    std::size_t index = 0;
    auto visit = [&](Json& f) {
        const AtlasFrame& frame = atlas.frames[index];
        add_polygons(f, frame, frame_analyses[index].boundary, stats, path + ": frame '" + frame.name + "'");
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

std::string atlas_polygons_json(const std::string& path, const Atlas& atlas, const std::vector<ImageAnalysis>& frames,
                                AtlasPolygonStats* stats) {
    return guarded(path, [&] { return polygons_json(path, atlas, frames, stats); });
}

} // namespace depthcull::io
