// Images by content, not by name: PNG (libpng), JPEG (libjpeg-turbo) and
// WebP (libwebp), all converted to RGBA8. JPEG has no alpha, so its texels
// are fully opaque (alpha 255), which the opaque-polygon analysis exploits;
// WebP without an alpha chunk decodes to alpha 255 the same way. What
// engines load but we read by an assumption (a CMYK JPEG's colours, an
// animated WebP's first frame) adds a warning line naming the file.
#include <csetjmp>
#include <cstddef>
#include <cstdio>

#include <jpeglib.h> // after <cstdio>: it uses FILE and size_t
#include <webp/decode.h>
#include <webp/demux.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "depthcull/io.h"
#include "io/formats.h"

namespace depthcull::io {

namespace {

enum class Format { png, jpeg, webp, unknown };

Format sniff(const unsigned char* b, std::size_t n) {
    if (n >= 8 && std::memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0) return Format::png;
    if (n >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff) return Format::jpeg;
    if (n >= 12 && std::memcmp(b, "RIFF", 4) == 0 && std::memcmp(b + 8, "WEBP", 4) == 0) return Format::webp;
    return Format::unknown;
}

std::string size_problem(long long w, long long h) {
    if (w <= 0 || h <= 0 || w > kMaxImageSide || h > kMaxImageSide || w * h > kMaxImageTexels)
        return "image size " + std::to_string(w) + "x" + std::to_string(h) + " is outside the supported 1.." +
               std::to_string(kMaxImageSide) + " per side";
    return {};
}

// libjpeg reports errors through error_exit, which must not return: we
// longjmp back to the caller, whose frame holds no C++ objects needing
// destruction between setjmp and the jump.
struct JpegError {
    jpeg_error_mgr mgr;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX];
};

void jpeg_error_exit(j_common_ptr cinfo) {
    auto* err = reinterpret_cast<JpegError*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, err->message);
    std::longjmp(err->jump, 1);
}

void jpeg_silent(j_common_ptr, int) {}

// Decodes into `pixels` (resized by the caller after the header through
// `on_size`); returns false with `err.message` set on a libjpeg error.
// *cmyk tells whether the file held CMYK (or YCCK) ink values, converted
// here to RGB.
bool jpeg_decode(const unsigned char* data, std::size_t size, bool header_only, int* width, int* height,
                 std::vector<std::uint8_t>* rgb, JpegError& err, const char** problem, bool* cmyk = nullptr) {
    jpeg_decompress_struct cinfo;
    cinfo.err = jpeg_std_error(&err.mgr);
    err.mgr.error_exit = jpeg_error_exit;
    err.mgr.emit_message = jpeg_silent;
    if (setjmp(err.jump)) {
        jpeg_destroy_decompress(&cinfo);
        return false;
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, data, static_cast<unsigned long>(size));
    jpeg_read_header(&cinfo, TRUE);
    *width = int(cinfo.image_width);
    *height = int(cinfo.image_height);
    if (header_only || !size_problem(cinfo.image_width, cinfo.image_height).empty()) {
        jpeg_destroy_decompress(&cinfo);
        return true;
    }
    // libjpeg converts no CMYK to RGB: it hands us the inks, and we make
    // RGB below as (1-C)(1-K) (no colour profile, as browsers without
    // colour management show it).
    const bool inks = cinfo.jpeg_color_space == JCS_CMYK || cinfo.jpeg_color_space == JCS_YCCK;
    if (cmyk) *cmyk = inks;
    cinfo.out_color_space = inks ? JCS_CMYK : JCS_EXT_RGBA; // libjpeg-turbo: alpha filled with 255
    jpeg_start_decompress(&cinfo);
    if (cinfo.output_components != 4) {
        *problem = "unexpected JPEG output components";
        jpeg_destroy_decompress(&cinfo);
        return false;
    }
    std::size_t stride = std::size_t(cinfo.output_width) * 4;
    if (rgb->size() != stride * cinfo.output_height) {
        *problem = "JPEG output size changed";
        jpeg_destroy_decompress(&cinfo);
        return false;
    }
    while (cinfo.output_scanline < cinfo.output_height) {
        JSAMPROW row = rgb->data() + stride * cinfo.output_scanline;
        jpeg_read_scanlines(&cinfo, &row, 1);
    }
    if (inks) {
        // Photoshop, which writes nearly every CMYK JPEG, stores inverted
        // inks (255: no ink) and marks its files with an Adobe APP14
        // segment; without one the values are plain inks.
        const bool inverted = cinfo.saw_Adobe_marker;
        for (std::size_t i = 0; i + 3 < rgb->size(); i += 4) {
            std::uint8_t* p = rgb->data() + i;
            const unsigned k = inverted ? p[3] : 255u - p[3];
            for (int c = 0; c < 3; ++c) p[c] = std::uint8_t(((inverted ? p[c] : 255u - p[c]) * k + 127) / 255);
            p[3] = 255;
        }
    }
    jpeg_finish_decompress(&cinfo);
    jpeg_destroy_decompress(&cinfo);
    return true;
}

void jpeg_size(std::string_view bytes, const std::string& name, int* w, int* h) {
    JpegError err{};
    const char* problem = nullptr;
    if (!jpeg_decode(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), true, w, h, nullptr, err, &problem))
        throw Error(name + ": corrupt JPEG (" + std::string(problem ? problem : err.message) + ")");
}

Image decode_jpeg(const void* data, std::size_t size, const std::string& name, std::vector<std::string>* warnings) {
    int w = 0, h = 0;
    JpegError err{};
    const char* problem = nullptr;
    const auto* bytes = static_cast<const unsigned char*>(data);
    if (!jpeg_decode(bytes, size, true, &w, &h, nullptr, err, &problem))
        throw Error(name + ": corrupt JPEG (" + std::string(err.message) + ")");
    if (std::string p = size_problem(w, h); !p.empty()) throw Error(name + ": " + p);
    Image image;
    image.width = w;
    image.height = h;
    guarded(name, [&] { image.rgba.resize(std::size_t(w) * std::size_t(h) * 4); });
    bool cmyk = false;
    if (!jpeg_decode(bytes, size, false, &w, &h, &image.rgba, err, &problem, &cmyk))
        throw Error(name + ": corrupt JPEG (" + std::string(problem ? problem : err.message) + ")");
    if (cmyk && warnings)
        warnings->push_back(name + ": CMYK JPEG: converted to RGB as (1-C)(1-K) without its colour profile (colours may differ from a "
                                   "colour-managed viewer's)");
    return image;
}

void webp_size(const void* data, std::size_t size, const std::string& name, int* w, int* h) {
    if (!WebPGetInfo(static_cast<const std::uint8_t*>(data), size, w, h)) throw Error(name + ": corrupt WebP (bad header)");
}

// An animated WebP's first frame, composited on its canvas (what a
// browser shows before it animates).
Image decode_webp_animation(const void* data, std::size_t size, const std::string& name, int w, int h,
                            std::vector<std::string>* warnings) {
    WebPAnimDecoderOptions options;
    if (!WebPAnimDecoderOptionsInit(&options)) throw Error(name + ": animated WebP: libwebp version mismatch");
    options.color_mode = MODE_RGBA;
    options.use_threads = 0;
    const WebPData bytes{static_cast<const std::uint8_t*>(data), size};
    WebPAnimDecoder* decoder = WebPAnimDecoderNew(&bytes, &options);
    if (!decoder) throw Error(name + ": corrupt animated WebP (bad animation chunks)");
    WebPAnimInfo info{};
    std::uint8_t* frame = nullptr;
    int timestamp = 0;
    const bool ok = WebPAnimDecoderGetInfo(decoder, &info) && int(info.canvas_width) == w && int(info.canvas_height) == h &&
                    WebPAnimDecoderGetNext(decoder, &frame, &timestamp);
    Image image;
    image.width = w;
    image.height = h;
    try {
        if (ok) guarded(name, [&] { image.rgba.assign(frame, frame + std::size_t(w) * std::size_t(h) * 4); });
    } catch (...) {
        WebPAnimDecoderDelete(decoder);
        throw;
    }
    WebPAnimDecoderDelete(decoder);
    if (!ok) throw Error(name + ": corrupt animated WebP (its first frame does not decode)");
    if (warnings)
        warnings->push_back(name + ": animated WebP (" + std::to_string(info.frame_count) + " frames): its first frame is used");
    return image;
}

Image decode_webp(const void* data, std::size_t size, const std::string& name, std::vector<std::string>* warnings) {
    int w = 0, h = 0;
    webp_size(data, size, name, &w, &h);
    if (std::string p = size_problem(w, h); !p.empty()) throw Error(name + ": " + p);
    WebPBitstreamFeatures features;
    if (WebPGetFeatures(static_cast<const std::uint8_t*>(data), size, &features) != VP8_STATUS_OK)
        throw Error(name + ": corrupt WebP (bad header)");
    if (features.has_animation) return decode_webp_animation(data, size, name, w, h, warnings);
    Image image;
    image.width = w;
    image.height = h;
    guarded(name, [&] { image.rgba.resize(std::size_t(w) * std::size_t(h) * 4); });
    if (!WebPDecodeRGBAInto(static_cast<const std::uint8_t*>(data), size, image.rgba.data(), image.rgba.size(), w * 4))
        throw Error(name + ": corrupt WebP (decoding failed)");
    return image;
}

[[noreturn]] void unknown_format(const std::string& name) {
    throw Error(name + " is not a PNG, JPEG or WebP image");
}

} // namespace

Image decode_image(const void* data, std::size_t size, const std::string& name, std::vector<std::string>* warnings) {
    switch (sniff(static_cast<const unsigned char*>(data), size)) {
    case Format::png: return decode_png(data, size, name);
    case Format::jpeg: return decode_jpeg(data, size, name, warnings);
    case Format::webp: return decode_webp(data, size, name, warnings);
    case Format::unknown: break;
    }
    unknown_format(name);
}

Image read_image(const std::string& path, std::vector<std::string>* warnings) {
    std::string bytes = read_file(path);
    return decode_image(bytes.data(), bytes.size(), path, warnings);
}

namespace {

void size_from_bytes(std::string_view bytes, const std::string& name, int* width, int* height) {
    int w = 0, h = 0;
    switch (sniff(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size())) {
    case Format::png: return png_size_from_bytes(bytes, name, width, height);
    case Format::jpeg: jpeg_size(bytes, name, &w, &h); break;
    case Format::webp: webp_size(bytes.data(), bytes.size(), name, &w, &h); break;
    case Format::unknown: unknown_format(name);
    }
    if (std::string p = size_problem(w, h); !p.empty()) throw Error(name + ": " + p);
    *width = w;
    *height = h;
}

} // namespace

void image_size(const std::string& path, int* width, int* height, ImageFiles* files) {
    if (const std::string* kept = files ? files->read(path) : nullptr) return size_from_bytes(*kept, path, width, height);
    // A PNG's size is in its first 24 bytes. JPEG and WebP sizes lie after
    // variable-length segments (EXIF can precede a JPEG's frame header), so
    // those files are read whole.
    const std::string head = read_image_head(path, 24);
    const Format f = sniff(reinterpret_cast<const unsigned char*>(head.data()), head.size());
    if (f == Format::unknown) unknown_format(path);
    size_from_bytes(f == Format::png ? head : read_file(path), path, width, height);
}

const std::string* ImageFiles::read(const std::string& path) {
    if (auto it = files_.find(path); it != files_.end()) return &it->second;
    // A missing or non-regular file has no size: null, and the caller's
    // read_image_head says what is wrong with it (and never opens a FIFO).
    std::error_code ec;
    const std::uint64_t size = std::filesystem::file_size(path, ec);
    if (ec || kept_ > budget_ || size > budget_ - kept_) return nullptr;
    std::string bytes = read_file(path);
    kept_ += bytes.size();
    return &files_.emplace(path, std::move(bytes)).first->second;
}

const std::string* ImageFiles::find(const std::string& path) const {
    auto it = files_.find(path);
    return it == files_.end() ? nullptr : &it->second;
}

} // namespace depthcull::io
