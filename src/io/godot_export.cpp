// Godot export: one text scene (.tscn, Godot 3's format 2, which Godot 4
// converts on import) per atlas frame, holding a Polygon2D that draws the
// frame through our boundary polygons: `polygon` the vertices in the
// untrimmed sprite's coordinates (origin at its top-left, y down, as
// Godot's), `uv` the same points in page texels (Godot's Polygon2D takes
// UVs in texture pixels), `polygons` one index triple per triangle of our
// ear clipping (boundary polygons may be concave).
#include <charconv>

#include "depthcull/io.h"
#include "io/formats.h"

namespace depthcull::io {

namespace {

void append_number(std::string& s, double v) {
    if (v == 0) v = 0; // no "-0"
    char text[32];
    auto [end, ec] = std::to_chars(text, text + sizeof text, v);
    s.append(text, ec == std::errc() ? end : text);
}

// Godot node names may not hold . : @ / " % (NodePath syntax).
std::string node_name(const std::string& name) {
    std::string out;
    for (char c : name) out += (c == '.' || c == ':' || c == '@' || c == '/' || c == '"' || c == '%' || c == '\\' || c < 32) ? '_' : c;
    return out.empty() ? "frame" : out;
}

std::string quoted(const std::string& text) {
    std::string out = "\"";
    for (char c : text) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

} // namespace

std::string godot_polygon_scene(const AtlasFrame& frame, const std::vector<Polygon>& boundary, const std::string& texture_path) {
    std::string polygon, uv, polygons;
    std::uint32_t base = 0;
    for (const Polygon& p : boundary) {
        std::vector<std::uint32_t> indices = triangulate_polygon(p);
        if (indices.empty() || indices.size() % 3 != 0) throw Error(frame.name + ": a boundary polygon could not be triangulated");
        for (const Vec2& v : p) {
            double s = v.x - frame.frame.x, t = v.y - frame.frame.y;
            Vec2 q = frame.rotated ? Vec2{t + frame.sprite_source.x, double(frame.frame.w) - s + frame.sprite_source.y}
                                   : Vec2{s + frame.sprite_source.x, t + frame.sprite_source.y};
            for (double c : {q.x, q.y}) {
                polygon += polygon.empty() ? "" : ", ";
                append_number(polygon, c);
            }
            for (double c : {v.x, v.y}) {
                uv += uv.empty() ? "" : ", ";
                append_number(uv, c);
            }
        }
        for (std::size_t i = 0; i < indices.size(); i += 3) {
            polygons += polygons.empty() ? "" : ", ";
            polygons += "PoolIntArray( " + std::to_string(base + indices[i]) + ", " + std::to_string(base + indices[i + 1]) + ", " +
                        std::to_string(base + indices[i + 2]) + " )";
        }
        base += std::uint32_t(p.size());
    }
    std::string s = "[gd_scene load_steps=2 format=2]\n\n[ext_resource path=" + quoted(texture_path) + " type=\"Texture\" id=1]\n\n";
    s += "[node name=" + quoted(node_name(frame.name)) + " type=\"Polygon2D\"]\n";
    s += "texture = ExtResource( 1 )\n";
    s += "polygon = PoolVector2Array( " + polygon + (polygon.empty() ? ")\n" : " )\n");
    s += "uv = PoolVector2Array( " + uv + (uv.empty() ? ")\n" : " )\n");
    s += "polygons = [ " + polygons + (polygons.empty() ? "]\n" : " ]\n");
    return s;
}

} // namespace depthcull::io
