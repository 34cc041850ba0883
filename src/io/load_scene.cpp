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

Scene load_scene(const std::string& path, const LoadOptions& options) {
    if (options.has_viewport) check_viewport(options.viewport, path + ": --viewport");
    return guarded(path, [&] {
        if (ends_with(path, ".tmx") || ends_with(path, ".tmx.gz")) return load_tiled_map(path, options);
        if (ends_with(path, ".json")) return load_scene_json(path, options);
        if (is_sprite_source(path)) return load_sprite_folder(path, options);
        throw Error(path + ": unknown scene format (expected .json, .tmx, .tmx.gz, a PNG or a directory of PNGs)");
    });
}

} // namespace depthcull::io
