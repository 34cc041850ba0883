// Tiled's JSON formats (maps .tmj / .json, tilesets .tsj / .json,
// templates .tj) read by translating them into the TMX document they
// stand for, so one reader (tiled_*.cpp) places, orders and checks both:
// the JSON and XML forms are written by the same Tiled serializer and name
// the same attributes ("tilewidth", "offsetx", "repeatx", ...), with layer
// "data" as a gid array (TMX: CSV) or a base64 string (with "encoding",
// "compression"), and layer kinds as "type" ("tilelayer" -> <layer>).
#include <nlohmann/json.hpp>

#include <cmath>

#include "io/tiled_internal.h"

namespace depthcull::io::tiled {

namespace {

using json = nlohmann::json;

std::string scalar_text(const json& v) {
    if (v.is_string()) return v.get<std::string>();
    if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
    if (v.is_number_integer()) return std::to_string(v.get<std::int64_t>());
    if (v.is_number_unsigned()) return std::to_string(v.get<std::uint64_t>());
    if (v.is_number_float()) {
        // A whole number written as 2.0 is the integer Tiled's reader takes
        // it for (QJsonValue::toInt); 2.5 or 1e300 stay as written, and an
        // integer attribute refuses them (int_attr).
        const double d = v.get<double>();
        if (std::fabs(d) < 0x1p53 && d == std::trunc(d)) return std::to_string(std::int64_t(d));
        return v.dump();
    }
    return {};
}

// Copies the scalar members named in `names` as attributes.
void copy_attributes(const json& from, pugi::xml_node to, std::initializer_list<const char*> names, const std::string& where) {
    for (const char* name : names) {
        auto it = from.find(name);
        if (it == from.end() || it->is_null()) continue;
        if (!it->is_primitive()) throw Error(where + ": \"" + name + "\" must be a string, number or boolean");
        to.append_attribute(name).set_value(scalar_text(*it).c_str());
    }
}

const json& member(const json& v, const char* name, const std::string& where) {
    auto it = v.find(name);
    if (it == v.end()) throw Error(where + ": missing \"" + name + "\"");
    return *it;
}

void check_object(const json& v, const std::string& where) {
    if (!v.is_object()) throw Error(where + ": must be a JSON object");
}

// Layer "data" (or a chunk's): an array of gids becomes CSV text, a
// string stays base64 text.
void add_cells(const json& data, pugi::xml_node node, const std::string& where) {
    if (data.is_string()) {
        node.text().set(data.get<std::string>().c_str());
        return;
    }
    if (!data.is_array()) throw Error(where + ": \"data\" must be an array of gids or a base64 string");
    std::string csv;
    csv.reserve(data.size() * 4);
    for (const json& gid : data) {
        if (!gid.is_number_unsigned() && !(gid.is_number_integer() && gid.get<std::int64_t>() >= 0))
            throw Error(where + ": \"data\" holds a value that is not a gid (a whole number 0..4294967295)");
        std::uint64_t g = gid.get<std::uint64_t>();
        if (g > 0xffffffffu) throw Error(where + ": \"data\" holds a gid above 4294967295");
        if (!csv.empty()) csv += ',';
        csv += std::to_string(g);
    }
    node.text().set(csv.c_str());
}

void convert_tileset(const json& ts, pugi::xml_node out, const std::string& where) {
    check_object(ts, where);
    copy_attributes(ts, out, {"firstgid", "source", "name", "tilewidth", "tileheight", "spacing", "margin", "tilecount", "columns",
                              "objectalignment", "tilerendersize", "fillmode"},
                    where);
    if (auto it = ts.find("tileoffset"); it != ts.end()) {
        check_object(*it, where + ": tileoffset");
        copy_attributes(*it, out.append_child("tileoffset"), {"x", "y"}, where + ": tileoffset");
    }
    if (auto it = ts.find("image"); it != ts.end()) {
        pugi::xml_node image = out.append_child("image");
        image.append_attribute("source").set_value(scalar_text(*it).c_str());
        if (auto t = ts.find("transparentcolor"); t != ts.end()) image.append_attribute("trans").set_value(scalar_text(*t).c_str());
    }
    if (auto it = ts.find("tiles"); it != ts.end()) {
        // Tiled 1.2+ writes an array of tiles with "id"; older files an
        // object keyed by the id.
        if (!it->is_array() && !it->is_object()) throw Error(where + ": \"tiles\" must be an array or an object");
        for (auto entry = it->begin(); entry != it->end(); ++entry) {
            const json& tile = *entry;
            std::string here = where + ": tile" + (it->is_object() ? " " + entry.key() : std::string());
            check_object(tile, here);
            pugi::xml_node node = out.append_child("tile");
            if (it->is_object()) node.append_attribute("id").set_value(entry.key().c_str());
            copy_attributes(tile, node, {"id", "x", "y", "width", "height"}, here);
            if (auto image = tile.find("image"); image != tile.end()) {
                pugi::xml_node img = node.append_child("image");
                img.append_attribute("source").set_value(scalar_text(*image).c_str());
                if (auto t = tile.find("transparentcolor"); t != tile.end()) img.append_attribute("trans").set_value(scalar_text(*t).c_str());
            }
            if (auto anim = tile.find("animation"); anim != tile.end()) {
                if (!anim->is_array()) throw Error(here + ": \"animation\" must be an array");
                pugi::xml_node a = node.append_child("animation");
                for (const json& frame : *anim) {
                    check_object(frame, here + ": animation frame");
                    copy_attributes(frame, a.append_child("frame"), {"tileid", "duration"}, here + ": animation frame");
                }
            }
        }
    }
}

void convert_object(const json& o, pugi::xml_node out, const std::string& where) {
    check_object(o, where);
    copy_attributes(o, out, {"id", "name", "gid", "x", "y", "width", "height", "rotation", "visible", "template"}, where);
    // Shapes Tiled marks with flags: kept as their XML children so they
    // stay "not an image" (the reader skips objects without a gid).
}

void convert_layers(const json& layers, pugi::xml_node parent, const std::string& where, int depth) {
    if (depth > limits::kMaxNestingDepth)
        throw Error(where + ": groups nested deeper than " + std::to_string(limits::kMaxNestingDepth) + " (kMaxNestingDepth)");
    if (!layers.is_array()) throw Error(where + ": \"layers\" must be an array");
    for (const json& layer : layers) {
        check_object(layer, where + ": layer");
        std::string type = scalar_text(member(layer, "type", where + ": layer"));
        std::string here = where + ": layer '" + (layer.contains("name") ? scalar_text(layer["name"]) : std::string()) + "'";
        const char* element = type == "tilelayer" ? "layer" : type == "objectgroup" ? "objectgroup" : type == "imagelayer" ? "imagelayer"
                              : type == "group" ? "group" : nullptr;
        if (!element) throw Error(here + ": unknown layer type '" + type + "'");
        pugi::xml_node node = parent.append_child(element);
        copy_attributes(layer, node, {"id", "name", "visible", "opacity", "offsetx", "offsety", "tintcolor", "parallaxx", "parallaxy",
                                      "width", "height", "draworder", "repeatx", "repeaty", "class", "mode"},
                        here);
        if (type == "tilelayer") {
            pugi::xml_node data = node.append_child("data");
            std::string encoding = layer.contains("encoding") ? scalar_text(layer["encoding"]) : "csv";
            if (encoding != "csv" && encoding != "base64") throw Error(here + ": unsupported encoding '" + encoding + "'");
            data.append_attribute("encoding").set_value(encoding.c_str());
            if (layer.contains("compression") && !scalar_text(layer["compression"]).empty())
                data.append_attribute("compression").set_value(scalar_text(layer["compression"]).c_str());
            if (auto chunks = layer.find("chunks"); chunks != layer.end()) {
                if (!chunks->is_array()) throw Error(here + ": \"chunks\" must be an array");
                for (const json& chunk : *chunks) {
                    check_object(chunk, here + ": chunk");
                    pugi::xml_node c = data.append_child("chunk");
                    copy_attributes(chunk, c, {"x", "y", "width", "height"}, here + ": chunk");
                    add_cells(member(chunk, "data", here + ": chunk"), c, here + ": chunk");
                }
            } else if (auto cells = layer.find("data"); cells != layer.end()) {
                add_cells(*cells, data, here);
            } else {
                node.remove_child(data);
            }
        } else if (type == "objectgroup") {
            if (auto objects = layer.find("objects"); objects != layer.end()) {
                if (!objects->is_array()) throw Error(here + ": \"objects\" must be an array");
                for (const json& o : *objects) convert_object(o, node.append_child("object"), here + ": object");
            }
        } else if (type == "imagelayer") {
            if (auto image = layer.find("image"); image != layer.end() && !scalar_text(*image).empty()) {
                pugi::xml_node img = node.append_child("image");
                img.append_attribute("source").set_value(scalar_text(*image).c_str());
                if (auto t = layer.find("transparentcolor"); t != layer.end()) img.append_attribute("trans").set_value(scalar_text(*t).c_str());
            }
        } else {
            if (auto children = layer.find("layers"); children != layer.end()) convert_layers(*children, node, here, depth + 1);
        }
    }
}

json parse(std::string_view text, const std::string& path) {
    check_json_depth(text, path);
    json doc;
    try {
        doc = json::parse(text.begin(), text.end());
    } catch (const json::exception& e) {
        throw_json_error(e, text, path);
    }
    check_object(doc, path);
    return doc;
}

} // namespace

bool looks_like_json(std::string_view text) {
    // A UTF-8 byte order mark, as some editors save JSON (the parser skips
    // it too): such a .tmj was read as XML and refused as "XML error".
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    for (char c : text) {
        if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
        return c == '{';
    }
    return false;
}

void json_map_to_xml(std::string_view text, const std::string& path, pugi::xml_document& doc) {
    json m = parse(text, path);
    if (m.contains("type") && scalar_text(m["type"]) != "map")
        throw Error(path + ": a Tiled JSON file of type '" + scalar_text(m["type"]) + "', not a map");
    pugi::xml_node map = doc.append_child("map");
    copy_attributes(m, map, {"orientation", "renderorder", "width", "height", "tilewidth", "tileheight", "infinite", "staggeraxis",
                             "staggerindex", "hexsidelength", "backgroundcolor", "parallaxoriginx", "parallaxoriginy"},
                    path);
    if (auto tilesets = m.find("tilesets"); tilesets != m.end()) {
        if (!tilesets->is_array()) throw Error(path + ": \"tilesets\" must be an array");
        int n = 0;
        for (const json& ts : *tilesets) convert_tileset(ts, map.append_child("tileset"), path + ": tileset " + std::to_string(n++));
    }
    convert_layers(member(m, "layers", path), map, path, 0);
}

void json_tileset_to_xml(std::string_view text, const std::string& path, pugi::xml_document& doc) {
    json ts = parse(text, path);
    if (ts.contains("type") && scalar_text(ts["type"]) != "tileset")
        throw Error(path + ": a Tiled JSON file of type '" + scalar_text(ts["type"]) + "', not a tileset");
    json copy = ts;
    copy.erase("firstgid"); // an external tileset's firstgid is the map's
    copy.erase("source");
    convert_tileset(copy, doc.append_child("tileset"), path);
}

void json_template_to_xml(std::string_view text, const std::string& path, pugi::xml_document& doc) {
    json t = parse(text, path);
    pugi::xml_node root = doc.append_child("template");
    if (auto ts = t.find("tileset"); ts != t.end()) {
        check_object(*ts, path + ": tileset");
        copy_attributes(*ts, root.append_child("tileset"), {"firstgid", "source"}, path + ": tileset");
    }
    convert_object(member(t, "object", path), root.append_child("object"), path + ": object");
}

} // namespace depthcull::io::tiled
