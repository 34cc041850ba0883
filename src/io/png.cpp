// PNG in through libpng's full API (every colour type to RGBA8, with no
// gamma conversion: see png_decode), out through its simplified API.
#include <png.h>

#include <cerrno>
#include <csetjmp>
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

namespace {

// libpng reports errors through its error function, which must not
// return: we longjmp back to decode_png's frame (no C++ objects live
// between its setjmp and the jump), as the JPEG reader does.
struct PngError {
    std::jmp_buf jump;
    char message[160];
};

void png_error_exit(png_structp png, png_const_charp message) {
    auto* err = static_cast<PngError*>(png_get_error_ptr(png));
    std::snprintf(err->message, sizeof err->message, "%s", message ? message : "error");
    std::longjmp(err->jump, 1);
}

void png_silent(png_structp, png_const_charp) {}

constexpr const char* kOutOfMemory = "out of memory"; // told apart by address

struct PngMemory {
    const unsigned char* data;
    std::size_t size, at;
};

void png_read_memory(png_structp png, png_bytep out, png_size_t n) {
    auto* in = static_cast<PngMemory*>(png_get_io_ptr(png));
    if (n > in->size - in->at) png_error(png, "file ends early");
    std::memcpy(out, in->data + in->at, n);
    in->at += n;
}

// The decode proper: null on success, else why not (or "" with `problem`
// set when the size is over our limits). `image` and `rows` are the
// caller's, so no C++ object of this frame lives across a longjmp.
const char* png_decode(const unsigned char* data, std::size_t size, PngError& err, Image& image,
                       std::vector<png_bytep>& rows, const std::string& name, std::string& problem) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &err, png_error_exit, png_silent);
    if (!png) return kOutOfMemory;
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_read_struct(&png, nullptr, nullptr);
        return kOutOfMemory;
    }
    if (setjmp(err.jump)) {
        png_destroy_read_struct(&png, &info, nullptr);
        return err.message;
    }
    PngMemory in{data, size, 0};
    png_set_read_fn(png, &in, png_read_memory);
    // Ancillary chunks with bad CRCs are dropped with a (silent) warning,
    // as the simplified API we used before does.
    png_set_crc_action(png, PNG_CRC_DEFAULT, PNG_CRC_WARN_DISCARD);
    png_read_info(png, info);
    const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    problem = size_problem(w, h);
    if (!problem.empty()) {
        png_destroy_read_struct(&png, &info, nullptr);
        return "";
    }
    // The file's own sample values, as WebGL's texImage2D, stb_image and
    // Tiled read them: no png_set_gamma (a gAMA chunk changes nothing, so a
    // colour key compares against what the file holds), and 16-bit samples
    // rounded to 8 bits, not treated as linear light.
    const int colour = png_get_color_type(png, info);
    if (colour == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (colour == PNG_COLOR_TYPE_GRAY || colour == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
    png_set_expand(png); // low bit depths to 8, tRNS to alpha
    png_set_scale_16(png);
    png_set_add_alpha(png, 0xff, PNG_FILLER_AFTER);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_rowbytes(png, info) != std::size_t(w) * 4) {
        png_destroy_read_struct(&png, &info, nullptr);
        return "unexpected row size";
    }
    image.width = int(w);
    image.height = int(h);
    try {
        guarded(name, [&] {
            image.rgba.resize(std::size_t(w) * h * 4);
            rows.resize(h);
        });
    } catch (const Error&) {
        png_destroy_read_struct(&png, &info, nullptr);
        return kOutOfMemory;
    }
    for (png_uint_32 y = 0; y < h; ++y) rows[y] = image.rgba.data() + std::size_t(y) * w * 4;
    png_read_image(png, rows.data());
    // No png_read_end: chunks after the image data (text, a missing IEND)
    // change no texel, and browsers show such files.
    png_destroy_read_struct(&png, &info, nullptr);
    return nullptr;
}

// libpng allocates a chunk's declared length before it reads the chunk,
// so a 40-byte file whose text chunk says 2 GiB took 2 GiB (and -j N
// files N times that) before "file ends early". Every chunk libpng reads
// before the image data must fit in the bytes left; past the first IDAT,
// libpng reads only the image data (no png_read_end).
void check_chunk_lengths(const unsigned char* bytes, std::size_t size, const std::string& name) {
    std::size_t at = 8;
    while (size - at >= 8) {
        const std::uint32_t length = std::uint32_t(bytes[at]) << 24 | std::uint32_t(bytes[at + 1]) << 16 |
                                     std::uint32_t(bytes[at + 2]) << 8 | std::uint32_t(bytes[at + 3]);
        const std::string type(reinterpret_cast<const char*>(bytes + at + 4), 4);
        if (type == "IDAT") return;
        if (length > size - at - 8) {
            bool printable = true;
            for (char c : type) printable = printable && ((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z'));
            throw Error(name + ": corrupt PNG (chunk " + (printable ? "'" + type + "' " : std::string()) + "at byte " + std::to_string(at) +
                        " says " + std::to_string(length) + " bytes, but the file ends " + std::to_string(size - at - 8) + " bytes later)");
        }
        at += 8 + std::size_t(length);
        if (size - at < 4) return; // the CRC or the file ends: libpng says which
        at += 4;
    }
}

} // namespace

Image decode_png(const void* data, std::size_t size, const std::string& name) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    if (size < 8 || png_sig_cmp(bytes, 0, 8) != 0) throw Error(name + ": not a readable PNG (not a PNG signature)");
    check_chunk_lengths(bytes, size, name);
    PngError err{};
    Image image;
    std::vector<png_bytep> rows;
    std::string problem;
    const char* failed = png_decode(bytes, size, err, image, rows, name, problem);
    if (!problem.empty()) throw Error(name + ": " + problem);
    if (failed == kOutOfMemory) throw Error(name + ": out of memory");
    if (failed) throw Error(name + ": corrupt PNG (" + std::string(failed) + ")");
    return image;
}

Image read_png(const std::string& path) {
    std::string bytes = read_file(path);
    return decode_png(bytes.data(), bytes.size(), path);
}

std::uint32_t parse_color_key(const std::string& text, const std::string& where) {
    std::string_view hex = text;
    if (!hex.empty() && hex[0] == '#') hex.remove_prefix(1);
    std::uint32_t value = 0;
    auto [end, ec] = std::from_chars(hex.data(), hex.data() + hex.size(), value, 16);
    if (hex.size() != 6 || ec != std::errc() || end != hex.data() + hex.size())
        throw Error(where + ": colour key '" + text + "' is not RRGGBB hex");
    return value;
}

std::string color_key_text(std::uint32_t rgb) {
    char text[8];
    std::snprintf(text, sizeof text, "%06x", unsigned(rgb & 0xffffffu));
    return text;
}

void apply_color_key(Image& image, std::uint32_t rgb) {
    const std::uint8_t r = std::uint8_t(rgb >> 16), g = std::uint8_t(rgb >> 8), b = std::uint8_t(rgb);
    for (std::size_t i = 0; i + 3 < image.rgba.size(); i += 4)
        if (image.rgba[i] == r && image.rgba[i + 1] == g && image.rgba[i + 2] == b) image.rgba[i + 3] = 0;
}

Image read_scene_image(const SceneImage& image, const ImageFiles* files, std::vector<std::string>* warnings) {
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
    Image out = bytes ? decode_image(bytes->data(), bytes->size(), image.path, warnings) : read_image(image.path, warnings);
    if (image.has_trans) apply_color_key(out, image.trans);
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

void write_png(const std::string& path, ImageView image) { write_file_atomic(path, encode_png(image)); }

} // namespace depthcull::io
