// PNG in and out through libpng's simplified API, which converts every
// colour type (grey, palette + tRNS, 16-bit, RGB, RGBA) to RGBA8 for us.
#include <png.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "depthcull/io.h"
#include "io/formats.h"

namespace depthcull::io {

namespace {

// Empty when a w x h image is within our limits, else why not.
std::string size_problem(std::uint32_t w, std::uint32_t h) {
    if (w == 0 || h == 0 || w > std::uint32_t(kMaxImageSide) || h > std::uint32_t(kMaxImageSide) ||
        std::int64_t(w) * h > kMaxImageTexels)
        return "image size " + std::to_string(w) + "x" + std::to_string(h) + " is outside the supported 1.." +
               std::to_string(kMaxImageSide) + " per side";
    return {};
}

} // namespace

void png_size_from_bytes(std::string_view bytes, const std::string& name, int* width, int* height) {
    const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
    if (bytes.size() < 24 || std::memcmp(b, "\x89PNG\r\n\x1a\n", 8) != 0 || std::memcmp(b + 12, "IHDR", 4) != 0)
        throw Error(name + " is not a PNG image");
    auto be32 = [&](int o) { return (std::uint32_t(b[o]) << 24) | (std::uint32_t(b[o + 1]) << 16) | (std::uint32_t(b[o + 2]) << 8) | b[o + 3]; };
    const std::uint32_t w = be32(16), h = be32(20);
    if (std::string problem = size_problem(w, h); !problem.empty()) throw Error(name + ": " + problem);
    *width = int(w);
    *height = int(h);
}

void png_size(const std::string& path, int* width, int* height, ImageFiles* files) {
    if (const std::string* kept = files ? files->read(path) : nullptr) return png_size_from_bytes(*kept, path, width, height);
    png_size_from_bytes(read_image_head(path, 24), path, width, height);
}

Image decode_png(const void* data, std::size_t size, const std::string& name) {
    png_image png;
    std::memset(&png, 0, sizeof png);
    png.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_memory(&png, data, size))
        throw Error(name + ": not a readable PNG (" + png.message + ")");
    if (std::string problem = size_problem(png.width, png.height); !problem.empty()) {
        png_image_free(&png);
        throw Error(name + ": " + problem);
    }
    png.format = PNG_FORMAT_RGBA;
    Image image;
    image.width = int(png.width);
    image.height = int(png.height);
    guarded(name, [&] { image.rgba.resize(PNG_IMAGE_SIZE(png)); });
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

std::uint32_t parse_colour_key(const std::string& text, const std::string& where) {
    std::string_view hex = text;
    if (!hex.empty() && hex[0] == '#') hex.remove_prefix(1);
    std::uint32_t value = 0;
    auto [end, ec] = std::from_chars(hex.data(), hex.data() + hex.size(), value, 16);
    if (hex.size() != 6 || ec != std::errc() || end != hex.data() + hex.size())
        throw Error(where + ": colour key '" + text + "' is not RRGGBB hex");
    return value;
}

std::string colour_key_text(std::uint32_t rgb) {
    char text[8];
    std::snprintf(text, sizeof text, "%06x", unsigned(rgb & 0xffffffu));
    return text;
}

void apply_colour_key(Image& image, std::uint32_t rgb) {
    const std::uint8_t r = std::uint8_t(rgb >> 16), g = std::uint8_t(rgb >> 8), b = std::uint8_t(rgb);
    for (std::size_t i = 0; i + 3 < image.rgba.size(); i += 4)
        if (image.rgba[i] == r && image.rgba[i + 1] == g && image.rgba[i + 2] == b) image.rgba[i + 3] = 0;
}

Image load_scene_image(const SceneImage& image, const ImageFiles* files) {
    if (image.has_fill) {
        Image solid;
        solid.width = solid.height = kFillImageSide;
        solid.rgba.resize(std::size_t(kFillImageSide) * kFillImageSide * 4);
        for (std::size_t i = 0; i < solid.rgba.size(); i += 4) {
            solid.rgba[i] = std::uint8_t(image.fill >> 16);
            solid.rgba[i + 1] = std::uint8_t(image.fill >> 8);
            solid.rgba[i + 2] = std::uint8_t(image.fill);
            solid.rgba[i + 3] = 255;
        }
        return solid;
    }
    const std::string* bytes = files ? files->find(image.path) : nullptr;
    Image out = bytes ? decode_image(bytes->data(), bytes->size(), image.path) : load_image(image.path);
    if (image.has_trans) apply_colour_key(out, image.trans);
    return out;
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
