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
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

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

// ---- cocos2d-x format 3 plist with polygons

void xml_escape(std::string& out, const std::string& text) {
    for (char c : text) {
        if (c == '&') out += "&amp;";
        else if (c == '<') out += "&lt;";
        else if (c == '>') out += "&gt;";
        else out += c;
    }
}

std::string int_text(double v) { return std::to_string(std::llround(v)); }

// cocos2d-x parses "vertices" and "verticesUV" as integers (atoi). Our
// polygons' vertices lie on the texel grid or are rounded onto it when that
// keeps every texel inside and the polygons triangulable; otherwise the
// frame's rectangle is written (counted in rectangle_frames).
std::vector<Polygon> integer_polygons(ImageView page, const AtlasFrame& frame, const std::vector<Polygon>& polygons, Filter filter,
                                      bool* fell_back) {
    *fell_back = false;
    bool integral = true;
    std::vector<Polygon> rounded = polygons;
    for (Polygon& p : rounded)
        for (Vec2& v : p) {
            Vec2 r{std::round(v.x), std::round(v.y)};
            if (r.x != v.x || r.y != v.y) integral = false;
            v = {std::clamp(r.x, double(frame.frame.x), double(frame.frame.x + frame.frame.w)),
                 std::clamp(r.y, double(frame.frame.y), double(frame.frame.y + frame.frame.h))};
        }
    if (integral) return rounded;
    bool good = rounded.size() == 1 && count_uncontained_texels(page, frame.frame, rounded, filter) == 0;
    for (const Polygon& p : rounded) {
        std::vector<std::uint32_t> t = p.size() >= 3 ? triangulate_polygon(p) : std::vector<std::uint32_t>{};
        if (t.size() != 3 * (p.size() - 2)) good = false;
    }
    if (good) return rounded;
    *fell_back = true;
    const Rect& r = frame.frame;
    return {{{double(r.x), double(r.y)}, {double(r.x + r.w), double(r.y)}, {double(r.x + r.w), double(r.y + r.h)}, {double(r.x), double(r.y + r.h)}}};
}

std::string plist_text(const Atlas& atlas, const std::vector<ImageAnalysis>& analyses, ImageView page, Filter filter,
                       AtlasPolygonStats& stats) {
    std::string s = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                    "<!DOCTYPE plist PUBLIC \"-//Apple Computer//DTD PLIST 1.0//EN\" \"http://www.apple.com/DTDs/PropertyList-1.0.dtd\">\n"
                    "<plist version=\"1.0\">\n<dict>\n\t<key>frames</key>\n\t<dict>\n";
    auto key = [&](const char* indent, const std::string& k) {
        s += indent;
        s += "<key>";
        xml_escape(s, k);
        s += "</key>\n";
    };
    auto str = [&](const char* indent, const std::string& v) {
        s += indent;
        s += "<string>";
        xml_escape(s, v);
        s += "</string>\n";
    };
    for (std::size_t i = 0; i < atlas.frames.size(); ++i) {
        const AtlasFrame& f = atlas.frames[i];
        const int w = f.rotated ? f.frame.h : f.frame.w, h = f.rotated ? f.frame.w : f.frame.h;
        // cocos2d-x's spriteOffset: trimmed centre minus untrimmed centre, y up.
        double ox = f.sprite_source.x + w / 2.0 - f.source_w / 2.0, oy = f.source_h / 2.0 - (f.sprite_source.y + h / 2.0);
        char offset[64];
        std::snprintf(offset, sizeof offset, "{%g,%g}", ox, oy);
        key("\t\t", f.name);
        s += "\t\t<dict>\n\t\t\t<key>aliases</key>\n\t\t\t<array/>\n";
        key("\t\t\t", "spriteOffset");
        str("\t\t\t", offset);
        key("\t\t\t", "spriteSize");
        str("\t\t\t", "{" + std::to_string(w) + "," + std::to_string(h) + "}");
        key("\t\t\t", "spriteSourceSize");
        str("\t\t\t", "{" + std::to_string(f.source_w) + "," + std::to_string(f.source_h) + "}");
        key("\t\t\t", "textureRect");
        str("\t\t\t", "{{" + std::to_string(f.frame.x) + "," + std::to_string(f.frame.y) + "},{" + std::to_string(w) + "," + std::to_string(h) + "}}");
        key("\t\t\t", "textureRotated");
        s += f.rotated ? "\t\t\t<true/>\n" : "\t\t\t<false/>\n";
        bool fell_back = false;
        std::vector<Polygon> polygons =
            analyses[i].boundary.empty() ? std::vector<Polygon>{} : integer_polygons(page, f, analyses[i].boundary, filter, &fell_back);
        stats.rectangle_frames += fell_back;
        std::string triangles, vertices, uv;
        std::uint32_t base = 0;
        for (const Polygon& polygon : polygons) {
            std::vector<std::uint32_t> indices = triangulate_polygon(polygon);
            for (const Vec2& p : polygon) {
                Vec2 q = page_to_sprite(f, p);
                vertices += (vertices.empty() ? "" : " ") + int_text(q.x) + " " + int_text(q.y);
                uv += (uv.empty() ? "" : " ") + int_text(p.x) + " " + int_text(p.y);
            }
            for (std::uint32_t index : indices) triangles += (triangles.empty() ? "" : " ") + std::to_string(base + index);
            base += std::uint32_t(polygon.size());
            stats.vertices += std::int64_t(polygon.size());
            stats.triangles += std::int64_t(indices.size() / 3);
            stats.polygon_area += area(polygon);
        }
        key("\t\t\t", "triangles");
        str("\t\t\t", triangles);
        key("\t\t\t", "vertices");
        str("\t\t\t", vertices);
        key("\t\t\t", "verticesUV");
        str("\t\t\t", uv);
        s += "\t\t</dict>\n";
        stats.frames += 1;
        stats.frame_area += double(f.frame.w) * f.frame.h;
    }
    std::string image = std::filesystem::path(atlas.image_path).filename().string();
    s += "\t</dict>\n\t<key>metadata</key>\n\t<dict>\n\t\t<key>format</key>\n\t\t<integer>3</integer>\n"
         "\t\t<key>pixelFormat</key>\n\t\t<string>RGBA8888</string>\n\t\t<key>premultiplyAlpha</key>\n\t\t<false/>\n";
    key("\t\t", "realTextureFileName");
    str("\t\t", image);
    key("\t\t", "size");
    str("\t\t", "{" + std::to_string(page.width) + "," + std::to_string(page.height) + "}");
    key("\t\t", "textureFileName");
    str("\t\t", image);
    s += "\t</dict>\n</dict>\n</plist>\n";
    return s;
}

void check_frame_count(const std::string& path, const Atlas& atlas, const std::vector<ImageAnalysis>& frame_analyses) {
    if (frame_analyses.size() != atlas.frames.size())
        throw Error(path + ": " + std::to_string(frame_analyses.size()) + " frame analyses for " + std::to_string(atlas.frames.size()) +
                    " frames");
}

std::string polygons_json(const std::string& path, const Atlas& atlas, const std::vector<ImageAnalysis>& frame_analyses,
                          AtlasPolygonStats* stats_out) {
    check_frame_count(path, atlas, frame_analyses);
    AtlasPolygonStats stats;
    // The bytes the atlas was read from; a hand-made Atlas has none, and the
    // file is then read here and must still describe atlas.frames.
    std::string read;
    const std::string_view text = atlas.text ? std::string_view(*atlas.text) : std::string_view(read = read_file(path));
    check_json_document(text, path);
    Json doc = Json::parse(text);
    std::size_t index = 0;
    auto changed = [&] { return Error(path + ": its frames differ from the atlas read (was the file changed meanwhile?)"); };
    auto visit = [&](Json& f) {
        if (index >= atlas.frames.size()) throw changed();
        const AtlasFrame& frame = atlas.frames[index];
        add_polygons(f, frame, frame_analyses[index].boundary, stats, path + ": frame '" + frame.name + "'");
        ++index;
        stats.frames += 1;
        stats.frame_area += double(frame.frame.w) * frame.frame.h;
    };
    if (atlas.form == AtlasForm::json_multipack) {
        for (Json& texture : doc["textures"])
            for (Json& f : texture["frames"]) visit(f);
    } else if (Json& frames = doc["frames"]; frames.is_object()) {
        for (auto& [name, f] : frames.items()) visit(f);
    } else {
        for (Json& f : frames) visit(f);
    }
    if (index != atlas.frames.size()) throw changed();
    if (stats_out) *stats_out = stats;
    return doc.dump(1, '\t') + "\n";
}

std::string polygons_plist(const std::string& path, const Atlas& atlas, ImageView page, const std::vector<ImageAnalysis>& frame_analyses,
                           Filter filter, AtlasPolygonStats* stats_out) {
    check_frame_count(path, atlas, frame_analyses);
    if (atlas.pages.size() > 1)
        throw Error(path + ": a cocos2d-x plist holds one page; this multipack has " + std::to_string(atlas.pages.size()) +
                    " (write JSON, or one plist per page)");
    AtlasPolygonStats stats;
    std::string text = plist_text(atlas, frame_analyses, page, filter, stats);
    if (stats_out) *stats_out = stats;
    return text;
}

} // namespace

std::string atlas_polygons_json(const std::string& path, const Atlas& atlas, const std::vector<ImageAnalysis>& frames,
                                AtlasPolygonStats* stats) {
    return guarded(path, [&] { return polygons_json(path, atlas, frames, stats); });
}

std::string atlas_polygons_plist(const std::string& path, const Atlas& atlas, ImageView page, const std::vector<ImageAnalysis>& frames,
                                 Filter filter, AtlasPolygonStats* stats) {
    return guarded(path, [&] { return polygons_plist(path, atlas, page, frames, filter, stats); });
}

} // namespace depthcull::io
