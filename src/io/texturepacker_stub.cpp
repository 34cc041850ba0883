// STUB until the TexturePacker reader lands (issue 6).
#include "depthcull/io.h"

namespace depthcull::io {
const AtlasFrame* Atlas::find(const std::string&) const { return nullptr; }
Atlas load_texturepacker(const std::string& path) { throw Error(path + ": TexturePacker atlases not supported yet"); }
FramePlacement place_frame(const AtlasFrame& frame, const std::array<double, 6>& t) { return {frame.frame, t}; }
} // namespace depthcull::io
