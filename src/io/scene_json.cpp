// STUB: replaced by the scene-format implementation (issue 4).
#include "io/formats.h"

namespace depthcull::io {
Scene load_scene_json(const std::string& path, const LoadOptions&) { throw Error(path + ": scene JSON not implemented yet"); }
} // namespace depthcull::io
