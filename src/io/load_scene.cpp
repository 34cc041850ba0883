#include "io/formats.h"

namespace depthcull::io {

bool ends_with(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Scene load_scene(const std::string& path, const LoadOptions& options) {
    if (ends_with(path, ".tmx") || ends_with(path, ".tmx.gz")) return load_tiled_map(path, options);
    if (ends_with(path, ".json")) return load_scene_json(path, options);
    throw Error(path + ": unknown scene format (expected .json, .tmx or .tmx.gz)");
}

} // namespace depthcull::io
