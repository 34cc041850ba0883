#include "depthcull/image.h"

namespace depthcull {

namespace {

template <class Pred>
Mask make_mask(ImageView image, Rect rect, Pred pred) {
    Mask m;
    if (rect.empty() || !image.contains(rect)) return m;
    m.width = rect.w;
    m.height = rect.h;
    m.bits.resize(std::size_t(rect.w) * rect.h);
    for (int y = 0; y < rect.h; ++y) {
        const std::uint8_t* row = image.texel(rect.x, rect.y + y);
        std::uint8_t* out = &m.bits[std::size_t(y) * rect.w];
        for (int x = 0; x < rect.w; ++x) out[x] = pred(row[x * 4 + 3]) ? 1 : 0;
    }
    return m;
}

} // namespace

Mask nontransparent_mask(ImageView image, Rect rect) {
    return make_mask(image, rect, [](std::uint8_t a) { return !is_transparent(a); });
}

Mask opaque_mask(ImageView image, Rect rect) {
    return make_mask(image, rect, [](std::uint8_t a) { return is_opaque(a); });
}

} // namespace depthcull
