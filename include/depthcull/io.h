// depthcull: file formats and files. Everything here may do I/O and throws
// depthcull::io::Error, whose message is one line naming the file and what
// is wrong with it ("scene.json: element 3: unknown image id \"rok\"").
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "depthcull/image.h"
#include "depthcull/scene.h"

namespace depthcull::io {

struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// PNG of any colour type libpng reads (grey, palette with tRNS, 16-bit,
// RGB, RGBA), converted to RGBA8. Rejects images over kMaxImageSide /
// kMaxImageTexels.
Image load_png(const std::string& path);
Image decode_png(const void* data, std::size_t size, const std::string& name);
std::string encode_png(ImageView image);
void save_png(const std::string& path, ImageView image); // atomic

std::string read_file(const std::string& path);
// Writes to a temporary file beside `path`, then renames it over `path`, so
// a reader never sees a half-written file and a failure leaves none.
void write_file_atomic(const std::string& path, std::string_view bytes);

// Scene loading, by extension: .json (our scene format), .tmx / .tmx.gz
// (Tiled). Image sizes are filled in; images are not kept.
struct LoadOptions {
    bool has_viewport = false; // --viewport x,y,w,h
    Viewport viewport;
};
Scene load_scene(const std::string& path, const LoadOptions& options = {});

} // namespace depthcull::io
