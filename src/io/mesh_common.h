// Internal to src/io: helpers shared by the mesh writers.
#pragma once

#include <string>

#include "depthcull/scene.h"

namespace depthcull::io {

// image_path (absolute or relative to the cwd) as seen from the directory
// of output_path, so the meshes file finds its images wherever it is
// written; unchanged for stdout.
std::string output_relative_path(const std::string& image_path, const std::string& output_path);
const char* blend_name(Blend b);

} // namespace depthcull::io
