#include "depthcull/limits.h"
#include "io/formats.h"

namespace depthcull::io {

void check_json_depth(std::string_view text, const std::string& path) {
    int depth = 0;
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        char c = text[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > limits::kMaxNestingDepth)
                throw Error(path + ": JSON nested deeper than " + std::to_string(limits::kMaxNestingDepth) +
                            " levels at byte " + std::to_string(i) + " (kMaxNestingDepth)");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

} // namespace depthcull::io

namespace depthcull::io {

bool valid_utf8(std::string_view s) {
    std::size_t i = 0, n = s.size();
    while (i < n) {
        auto c = static_cast<unsigned char>(s[i]);
        int extra = c < 0x80 ? 0 : (c >> 5) == 0x6 ? 1 : (c >> 4) == 0xe ? 2 : (c >> 3) == 0x1e ? 3 : -1;
        if (extra < 0 || (extra > 0 && i + std::size_t(extra) >= n)) return false;
        std::uint32_t cp = extra == 0 ? c : c & (0x3fu >> extra);
        for (int k = 1; k <= extra; ++k) {
            auto d = static_cast<unsigned char>(s[i + std::size_t(k)]);
            if ((d >> 6) != 0x2) return false;
            cp = cp << 6 | (d & 0x3fu);
        }
        // Overlong forms, surrogates and code points past U+10FFFF.
        static const std::uint32_t least[4] = {0, 0x80, 0x800, 0x10000};
        if (cp < least[extra] || (cp >= 0xd800 && cp <= 0xdfff) || cp > 0x10ffff) return false;
        i += std::size_t(extra) + 1;
    }
    return true;
}

void check_utf8(const std::string& text, const std::string& where) {
    if (!valid_utf8(text)) throw Error(where + ": '" + text + "' is not valid UTF-8 (JSON text must be)");
}

} // namespace depthcull::io
