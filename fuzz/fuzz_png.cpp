// Fuzzes the PNG decoder (io::decode_png, libpng underneath): every input
// is an RGBA8 image within the size limits or a depthcull::Error, never a crash
// or a libpng longjmp out of our frames; what decodes encodes and decodes
// back to the same texels. Seeds: fuzz/corpus/png/.
#include <cstdlib>

#include "depthcull/io.h"
#include "depthcull/limits.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    depthcull::Image image;
    try {
        image = depthcull::io::decode_png(data, size, "fuzz.png");
    } catch (const depthcull::Error&) {
        return 0;
    }
    if (image.width <= 0 || image.height <= 0 || image.width > depthcull::kMaxImageSide || image.height > depthcull::kMaxImageSide)
        std::abort();
    if (image.rgba.size() != std::size_t(image.width) * std::size_t(image.height) * 4) std::abort();
    if (image.rgba.size() > 4 * 256 * 256) return 0; // keep iterations fast
    const std::string again = depthcull::io::encode_png(image.view());
    const depthcull::Image back = depthcull::io::decode_png(again.data(), again.size(), "again.png");
    if (back.width != image.width || back.height != image.height || back.rgba != image.rgba) std::abort();
    return 0;
}
