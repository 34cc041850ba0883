#include <cmath>

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

bool is_tiled(const std::string& path) { return ends_with(path, ".tmx") || ends_with(path, ".tmx.gz"); }

// `bytes` reads the file: load_scene reads it only once the format is known.
template <class Bytes>
Scene load(const std::string& path, const LoadOptions& options, Bytes&& bytes) {
    if (options.has_viewport) check_viewport(options.viewport, path + ": --viewport");
    return guarded(path, [&] {
        if (is_tiled(path)) return tiled_map_from_bytes(bytes(), path, options);
        if (ends_with(path, ".json")) return scene_json_from_text(bytes(), path, options);
        if (is_sprite_source(path)) return load_sprite_folder(path, options);
        throw Error(path + ": unknown scene format (expected .json, .tmx, .tmx.gz, a PNG or a directory of PNGs)");
    });
}

} // namespace

Scene load_scene(const std::string& path, const LoadOptions& options) {
    return load(path, options, [&] { return read_file(path); });
}

Scene load_scene_bytes(std::string_view bytes, const std::string& path, const LoadOptions& options) {
    return load(path, options, [&] { return bytes; });
}

} // namespace depthcull::io
