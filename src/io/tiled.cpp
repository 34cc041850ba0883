// STUB: replaced by the Tiled importer (issue 6).
#include "io/formats.h"

namespace depthcull::io {
Scene load_tiled_map(const std::string& path, const LoadOptions&) { throw Error(path + ": Tiled maps not supported yet"); }
} // namespace depthcull::io
