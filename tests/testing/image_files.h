// Small image files of the kinds engines load but that need care to read
// (issue 21): a PNG with a gAMA chunk or 16-bit samples, a CMYK JPEG as
// Photoshop writes it, an animated WebP. Written with libpng, libjpeg and
// libwebp in the test itself (header-only: only the test programs that
// include it link the codecs, through depthcull_io).
#pragma once

#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <jpeglib.h>
#include <png.h>
#include <webp/encode.h>

namespace depthcull::test {

// A w x h PNG of 8-bit RGB texels `rgb` (or 16-bit when `sixteen`, two
// big-endian bytes per sample), with a gAMA chunk of `gamma` when > 0.
inline std::string png_bytes(int w, int h, const std::vector<std::uint8_t>& samples, bool sixteen = false, double gamma = 0) {
    std::string out;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_set_write_fn(
        png, &out, [](png_structp p, png_bytep data, png_size_t n) { static_cast<std::string*>(png_get_io_ptr(p))->append(reinterpret_cast<char*>(data), n); },
        nullptr);
    png_set_IHDR(png, info, png_uint_32(w), png_uint_32(h), sixteen ? 16 : 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (gamma > 0) png_set_gAMA(png, info, gamma);
    png_write_info(png, info);
    const std::size_t stride = std::size_t(w) * 3 * (sixteen ? 2 : 1);
    for (int y = 0; y < h; ++y) png_write_row(png, samples.data() + std::size_t(y) * stride);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return out;
}

// A w x h CMYK JPEG of one colour, its inks stored inverted (255: no ink)
// with an Adobe APP14 segment, as Photoshop writes them.
inline std::string cmyk_jpeg_bytes(int w, int h, const std::uint8_t stored[4]) {
    jpeg_compress_struct cinfo;
    jpeg_error_mgr err;
    cinfo.err = jpeg_std_error(&err);
    jpeg_create_compress(&cinfo);
    unsigned char* buffer = nullptr;
    unsigned long size = 0;
    jpeg_mem_dest(&cinfo, &buffer, &size);
    cinfo.image_width = JDIMENSION(w);
    cinfo.image_height = JDIMENSION(h);
    cinfo.input_components = 4;
    cinfo.in_color_space = JCS_CMYK;
    jpeg_set_defaults(&cinfo);
    jpeg_set_colorspace(&cinfo, JCS_CMYK); // libjpeg writes the Adobe marker for it
    jpeg_set_quality(&cinfo, 100, TRUE);
    jpeg_start_compress(&cinfo, TRUE);
    std::vector<std::uint8_t> row(std::size_t(w) * 4);
    for (std::size_t i = 0; i < row.size(); ++i) row[i] = stored[i % 4];
    while (cinfo.next_scanline < cinfo.image_height) {
        JSAMPROW r = row.data();
        jpeg_write_scanlines(&cinfo, &r, 1);
    }
    jpeg_finish_compress(&cinfo);
    std::string out(reinterpret_cast<char*>(buffer), size);
    jpeg_destroy_compress(&cinfo);
    std::free(buffer);
    return out;
}

// An animated WebP of w x h frames, each one colour (RGBA), built by hand
// (RIFF, VP8X with the animation flag, ANIM, one ANMF per frame holding a
// lossless VP8L bitstream from libwebp's still encoder).
inline std::string animated_webp_bytes(int w, int h, const std::vector<std::uint32_t>& colours) {
    auto le = [](std::string& s, std::uint32_t v, int bytes) {
        for (int i = 0; i < bytes; ++i) s.push_back(char((v >> (8 * i)) & 0xff));
    };
    auto chunk = [&](const char* tag, const std::string& payload) {
        std::string c(tag, 4);
        le(c, std::uint32_t(payload.size()), 4);
        c += payload;
        if (payload.size() % 2) c.push_back('\0');
        return c;
    };
    std::string body = "WEBP";
    std::string vp8x;
    vp8x.push_back(char(0x02 | 0x10)); // animation, alpha
    vp8x.append(3, '\0');
    le(vp8x, std::uint32_t(w - 1), 3);
    le(vp8x, std::uint32_t(h - 1), 3);
    body += chunk("VP8X", vp8x);
    std::string anim;
    le(anim, 0, 4); // background colour
    le(anim, 0, 2); // loop forever
    body += chunk("ANIM", anim);
    for (std::uint32_t colour : colours) {
        std::vector<std::uint8_t> rgba(std::size_t(w) * h * 4);
        for (std::size_t i = 0; i < rgba.size(); ++i) rgba[i] = std::uint8_t(colour >> (24 - 8 * (i % 4)));
        std::uint8_t* encoded = nullptr;
        const std::size_t n = WebPEncodeLosslessRGBA(rgba.data(), w, h, w * 4, &encoded);
        const std::string still(reinterpret_cast<char*>(encoded), n);
        WebPFree(encoded);
        std::string anmf;
        le(anmf, 0, 3); // x / 2
        le(anmf, 0, 3); // y / 2
        le(anmf, std::uint32_t(w - 1), 3);
        le(anmf, std::uint32_t(h - 1), 3);
        le(anmf, 100, 3);        // duration (ms)
        anmf.push_back(char(0x02)); // no blending, no disposal
        anmf += still.substr(12);   // the VP8L chunk after the still's RIFF header
        body += chunk("ANMF", anmf);
    }
    std::string out = "RIFF";
    le(out, std::uint32_t(body.size()), 4);
    return out + body;
}

} // namespace depthcull::test
