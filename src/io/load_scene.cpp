#include <cmath>

#include <nlohmann/json.hpp>

#include "depthcull/limits.h"
#include "io/formats.h"

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

namespace {

// A .json scene is ours or a Tiled map: decided by the first top-level key
// that only one of them has, reading no further than that key.
struct FirstKeySax : nlohmann::json_sax<nlohmann::json> {
    int depth = 0;
    int verdict = 0; // 1: Tiled map, -1: our scene
    bool null() override { return true; }
    bool boolean(bool) override { return true; }
    bool number_integer(number_integer_t) override { return true; }
    bool number_unsigned(number_unsigned_t) override { return true; }
    bool number_float(number_float_t, const string_t&) override { return true; }
    bool string(string_t&) override { return true; }
    bool binary(binary_t&) override { return true; }
    bool start_object(std::size_t) override { return ++depth, true; }
    bool end_object() override { return --depth, true; }
    bool start_array(std::size_t) override { return ++depth, true; }
    bool end_array() override { return --depth, true; }
    bool key(string_t& k) override {
        if (depth != 1) return true;
        if (k == "layers" || k == "tilesets" || k == "tiledversion" || k == "orientation") verdict = 1;
        else if (k == "elements" || k == "images") verdict = -1;
        return verdict == 0;
    }
    bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }
};

bool is_tiled_json(const std::string& path) {
    std::string text = read_file(path);
    FirstKeySax sax;
    nlohmann::json::sax_parse(text, &sax);
    return sax.verdict == 1;
}

} // namespace

Scene load_scene(const std::string& path, const LoadOptions& options) {
    if (options.has_viewport) check_viewport(options.viewport, path + ": --viewport");
    return guarded(path, [&] {
        if (ends_with(path, ".tmx") || ends_with(path, ".tmx.gz") || ends_with(path, ".tmj") || ends_with(path, ".tmj.gz"))
            return load_tiled_map(path, options);
        if (ends_with(path, ".json.gz")) return load_tiled_map(path, options); // Tiled's gzipped JSON maps
        if (ends_with(path, ".json")) return is_tiled_json(path) ? load_tiled_map(path, options) : load_scene_json(path, options);
        throw Error(path + ": unknown scene format (expected .json, .tmx, .tmj, or either gzipped)");
    });
}

} // namespace depthcull::io
