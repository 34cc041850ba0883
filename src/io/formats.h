// Internal: the scene readers that io::load_scene dispatches to.
#pragma once

#include <string>

#include "depthcull/io.h"

namespace depthcull::io {

Scene load_scene_json(const std::string& path, const LoadOptions& options); // scene_json.cpp
Scene load_tiled_map(const std::string& path, const LoadOptions& options);  // tiled.cpp

// Width and height from the PNG signature and IHDR chunk, without decoding;
// io::Error when the file is missing, not a PNG, or over our size limits.
void png_size(const std::string& path, int* width, int* height); // png.cpp

bool ends_with(const std::string& s, const std::string& suffix);

} // namespace depthcull::io
