#include <algorithm>
#include <charconv>
#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "depthcull/limits.h"
#include "io/formats.h"
#include "io/json_keys.h"

namespace depthcull::io {

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void check_viewport(const Viewport& v, const std::string& where) {
    if (!(std::fabs(v.x) <= limits::kMaxCoordinate && std::fabs(v.y) <= limits::kMaxCoordinate))
        throw Error(where + ": x and y must be finite and within +-1e9 (kMaxCoordinate)");
    if (v.width <= 0 || v.height <= 0 || v.width > kMaxImageSide || v.height > kMaxImageSide)
        throw Error(where + ": width and height must be 1.." + std::to_string(kMaxImageSide) + " (kMaxImageSide)");
}

void report_warnings(const std::vector<std::string>& lines, const LoadOptions& options) {
    if (options.strict && !lines.empty()) throw Error(lines.front() + " (--strict)");
    std::set<std::string> seen;
    for (const std::string& line : lines)
        if (seen.insert(line).second && options.warning) options.warning(line);
}

namespace {

// A .json scene is ours or a Tiled map: decided by the first top-level key
// that only one of them has, reading no further than that key.
bool is_tiled_json(std::string_view text) {
    int verdict = 0; // 1: Tiled map, -1: our scene
    scan_json_keys(text, [&](int depth, std::string_view k) {
        if (depth != 1) return true;
        if (k == "layers" || k == "tilesets" || k == "tiledversion" || k == "orientation") verdict = 1;
        else if (k == "elements" || k == "images") verdict = -1;
        return verdict == 0;
    });
    return verdict == 1;
}

bool is_tiled(const std::string& path) {
    for (const char* ext : {".tmx", ".tmx.gz", ".tmj", ".tmj.gz", ".json.gz"}) // .json.gz: Tiled's gzipped JSON maps
        if (ends_with(path, ext)) return true;
    return false;
}

// LoadOptions::insert_at for a scene that is not a Tiled map: element
// indices, 0..elements (on top), added to the scene's own points.
Scene with_insertion_points(Scene scene, const std::string& path, const LoadOptions& options) {
    for (const std::string& text : options.insert_at) {
        std::size_t index = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), index);
        if (text.empty() || ec != std::errc() || end != text.data() + text.size() || index > scene.elements.size())
            throw Error(path + ": --insert-at '" + text + "': not an element index in 0.." + std::to_string(scene.elements.size()) +
                        " (layer names are for Tiled maps)");
        scene.insertion_points.push_back(index);
    }
    std::sort(scene.insertion_points.begin(), scene.insertion_points.end());
    scene.insertion_points.erase(std::unique(scene.insertion_points.begin(), scene.insertion_points.end()), scene.insertion_points.end());
    return scene;
}

// `bytes` reads the file: read_scene reads it only once the format is known.
template <class Bytes>
Scene load(const std::string& path, const LoadOptions& options, Bytes&& bytes) {
    if (options.has_viewport) check_viewport(options.viewport, path + ": --viewport");
    return guarded(path, [&] {
        if (is_tiled(path)) return tiled_map_from_bytes(bytes(), path, options);
        if (ends_with(path, ".json")) {
            // A .json scene is ours or a Tiled map: its first telling key decides.
            const auto text = bytes();
            return is_tiled_json(text) ? tiled_map_from_bytes(text, path, options)
                                       : with_insertion_points(scene_json_from_text(text, path, options), path, options);
        }
        if (is_sprite_source(path)) return with_insertion_points(read_sprite_folder(path, options), path, options);
        throw Error(path + ": unknown scene format (expected .json, .tmx, .tmj, either gzipped, a PNG or a directory of PNGs)");
    });
}

} // namespace

Scene read_scene(const std::string& path, const LoadOptions& options) {
    if (options.documents) options.documents->push_back(path);
    return load(path, options, [&] { return read_file(path); });
}

Scene scene_from_bytes(std::string_view bytes, const std::string& path, const LoadOptions& options) {
    return load(path, options, [&] { return bytes; });
}

} // namespace depthcull::io
