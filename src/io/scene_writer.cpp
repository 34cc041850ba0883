// Writes a Scene in our scene JSON format (read by scene_json.cpp):
//   { "viewport": {"x", "y", "width", "height"}, "filter": "nearest",
//     "images": [{"id", "path"}],
//     "elements": [{"image": id, "rect": [x,y,w,h], "transform": [a,b,c,d,e,f],
//                   "color": [r,g,b,a], "blend": "alpha"}] }
// Output is deterministic: fixed key order, shortest round-trip numbers,
// integral values written as integers.
#include <charconv>
#include <cmath>

#include <nlohmann/json.hpp>

#include "depthcull/io.h"
#include "io/formats.h"
#include "io/mesh_common.h"

namespace depthcull::io {

namespace {

using Json = nlohmann::ordered_json;

Json number(double v) {
    if (v == 0) return 0; // no "-0"
    if (std::abs(v) < 9.0e15 && v == std::floor(v)) return std::int64_t(v);
    return v;
}

// A float as the double its shortest decimal form reads back as, so 0.3f
// is written "0.3", not "0.30000001192092896".
Json number(float v) {
    char text[32];
    auto [end, ec] = std::to_chars(text, text + sizeof text, v);
    double d = 0;
    std::from_chars(text, end, d);
    return number(d);
}

} // namespace

std::string scene_to_json_text(const Scene& scene, const std::string& output_path) {
    Json doc;
    doc["viewport"] = {{"x", number(scene.viewport.x)},
                       {"y", number(scene.viewport.y)},
                       {"width", scene.viewport.width},
                       {"height", scene.viewport.height}};
    doc["filter"] = scene.filter == Filter::linear ? "linear" : "nearest";
    Json images = Json::array();
    for (const SceneImage& image : scene.images) {
        if (image.has_fill) {
            check_utf8(image.id, output_name(output_path) + ": image id");
            images.push_back({{"id", image.id}, {"fill", color_key_text(image.fill)}});
            continue;
        }
        std::string path = output_relative_path(image.path, output_path);
        check_utf8(image.id, output_name(output_path) + ": image id");
        check_utf8(path, output_name(output_path) + ": image \"" + image.id + "\": path");
        Json entry = {{"id", image.id}, {"path", std::move(path)}};
        if (image.has_trans) entry["trans"] = color_key_text(image.trans);
        images.push_back(std::move(entry));
    }
    doc["images"] = std::move(images);
    Json elements = Json::array();
    for (std::size_t i = 0; i < scene.elements.size(); ++i) {
        const Element& e = scene.elements[i];
        if (e.image < 0 || std::size_t(e.image) >= scene.images.size())
            throw Error(output_path + ": element " + std::to_string(i) + " names image " + std::to_string(e.image) +
                        " of " + std::to_string(scene.images.size()));
        Json transform = Json::array();
        for (double v : e.transform) transform.push_back(number(v));
        Json color = Json::array();
        for (float v : e.color) color.push_back(number(v));
        Json entry = {{"image", scene.images[std::size_t(e.image)].id},
                      {"rect", {e.rect.x, e.rect.y, e.rect.w, e.rect.h}},
                      {"transform", std::move(transform)},
                      {"color", std::move(color)},
                      {"blend", blend_name(e.blend)}};
        if (e.animation >= 0) entry["animation"] = e.animation;
        elements.push_back(std::move(entry));
    }
    doc["elements"] = std::move(elements);
    if (!scene.animations.empty()) {
        Json animations = Json::array();
        for (const Animation& a : scene.animations) {
            Json frames = Json::array();
            for (const AnimationFrame& f : a.frames)
                frames.push_back({{"image", scene.images.at(std::size_t(f.image)).id},
                                  {"rect", {f.rect.x, f.rect.y, f.rect.w, f.rect.h}},
                                  {"duration", f.duration_ms}});
            animations.push_back({{"frames", std::move(frames)}});
        }
        doc["animations"] = std::move(animations);
    }
    if (!scene.insertion_points.empty()) doc["insertion_points"] = scene.insertion_points;
    // One element per line: readable diffs, and far smaller than dump(2).
    std::string text = "{\n";
    bool first = true;
    for (auto& [key, value] : doc.items()) {
        text += first ? "  " : ",\n  ";
        first = false;
        text += Json(key).dump() + ": ";
        if (value.is_array() && !value.empty()) {
            text += "[\n";
            for (std::size_t i = 0; i < value.size(); ++i) text += "    " + value[i].dump() + (i + 1 < value.size() ? ",\n" : "\n");
            text += "  ]";
        } else {
            text += value.dump();
        }
    }
    text += "\n}\n";
    return text;
}

void write_scene_json(const std::string& path, const Scene& scene) { write_file_atomic(path, scene_to_json_text(scene, path)); }

} // namespace depthcull::io
