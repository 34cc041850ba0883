// STUB until the scene pipeline lands (issue 4).
#include "depthcull/io.h"

namespace depthcull::io {
PreparedScene prepare_scene(const std::string& path, const PrepareOptions&) { throw Error(path + ": prepare_scene not implemented yet"); }
} // namespace depthcull::io
