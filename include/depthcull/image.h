// depthcull: images and texels.
//
// Texel (i, j) covers the square [i, i+1] x [j, j+1] of texel space; y points
// down. A texel is *transparent* when alpha == 0 and *opaque* when
// alpha == 255 (paper 2.1, 2.2). The core never owns pixels it analyzes: it
// reads them through an ImageView, so atlases and tilesets are analyzed in
// place, one sub-rectangle at a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace depthcull {

// An axis-aligned rectangle of texels: [x, x+w) x [y, y+h).
struct Rect {
    int x = 0, y = 0, w = 0, h = 0;

    bool empty() const { return w <= 0 || h <= 0; }
    friend bool operator==(const Rect&, const Rect&) = default;
};

// Limits on what we accept, so a hostile file cannot make us allocate
// without bound. 16384 is the largest texture most GPUs sample.
inline constexpr int kMaxImageSide = 16384;
inline constexpr std::int64_t kMaxImageTexels = std::int64_t(1) << 28;

// Read-only RGBA8 texels, rows `stride` bytes apart.
struct ImageView {
    const std::uint8_t* rgba = nullptr;
    int width = 0, height = 0;
    std::ptrdiff_t stride = 0;

    const std::uint8_t* texel(int x, int y) const { return rgba + y * stride + std::ptrdiff_t(x) * 4; }
    std::uint8_t alpha(int x, int y) const { return texel(x, y)[3]; }
    bool contains(const Rect& r) const {
        return r.x >= 0 && r.y >= 0 && r.w >= 0 && r.h >= 0 && r.x <= width - r.w && r.y <= height - r.h;
    }
    Rect bounds() const { return {0, 0, width, height}; }
};

// An owned RGBA8 image (non-premultiplied, as PNG stores it).
struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba; // width * height * 4 bytes

    ImageView view() const { return {rgba.data(), width, height, std::ptrdiff_t(width) * 4}; }
};

// Alpha classes of paper 2.1 / 2.2.
inline bool is_transparent(std::uint8_t alpha) { return alpha == 0; }
inline bool is_opaque(std::uint8_t alpha) { return alpha == 255; }

// A binary texel mask over a rectangle, row-major, 1 byte per texel. Used to
// hand the boundary and opaque stages the texel classes they care about.
struct Mask {
    int width = 0, height = 0;
    std::vector<std::uint8_t> bits;

    bool at(int x, int y) const { return bits[std::size_t(y) * width + x] != 0; }
};

// Texels of `rect` with alpha > 0 (non-transparent); coordinates relative to rect.
Mask nontransparent_mask(ImageView image, Rect rect);
// Texels of `rect` with alpha == 255 (opaque); coordinates relative to rect.
Mask opaque_mask(ImageView image, Rect rect);

} // namespace depthcull
