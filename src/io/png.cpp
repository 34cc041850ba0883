// PNG in and out through libpng's simplified API, which converts every
// colour type (grey, palette + tRNS, 16-bit, RGB, RGBA) to RGBA8 for us.
#include <png.h>

#include <cstring>

#include "depthcull/io.h"

namespace depthcull::io {

Image decode_png(const void* data, std::size_t size, const std::string& name) {
    png_image png;
    std::memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&png, data, size))
        throw Error(name + ": not a readable PNG (" + png.message + ")");
    if (png.width == 0 || png.height == 0 || png.width > unsigned(kMaxImageSide) || png.height > unsigned(kMaxImageSide) ||
        std::int64_t(png.width) * png.height > kMaxImageTexels) {
        std::string size_text = std::to_string(png.width) + "x" + std::to_string(png.height);
        png_image_free(&png);
        throw Error(name + ": image size " + size_text + " is outside the supported 1.." + std::to_string(kMaxImageSide) +
                    " per side");
    }
    png.format = PNG_FORMAT_RGBA;
    Image image;
    image.width = int(png.width);
    image.height = int(png.height);
    image.rgba.resize(PNG_IMAGE_SIZE(png));
    if (!png_image_finish_read(&png, nullptr, image.rgba.data(), 0, nullptr)) {
        std::string message = png.message;
        png_image_free(&png);
        throw Error(name + ": corrupt PNG (" + message + ")");
    }
    return image;
}

Image load_png(const std::string& path) {
    std::string bytes = read_file(path);
    return decode_png(bytes.data(), bytes.size(), path);
}

std::string encode_png(ImageView image) {
    png_image png;
    std::memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    png.width = png_uint_32(image.width);
    png.height = png_uint_32(image.height);
    png.format = PNG_FORMAT_RGBA;
    png_alloc_size_t size = 0;
    if (!png_image_write_to_memory(&png, nullptr, &size, 0, image.rgba, png_int_32(image.stride), nullptr))
        throw Error(std::string("PNG encoding failed: ") + png.message);
    std::string out(size, '\0');
    if (!png_image_write_to_memory(&png, out.data(), &size, 0, image.rgba, png_int_32(image.stride), nullptr))
        throw Error(std::string("PNG encoding failed: ") + png.message);
    out.resize(size);
    return out;
}

void save_png(const std::string& path, ImageView image) { write_file_atomic(path, encode_png(image)); }

} // namespace depthcull::io
