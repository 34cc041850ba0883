#include <cmath>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "depthcull/limits.h"
#include "io/formats.h"

namespace depthcull::io {

namespace {

// The 0-based offset of the first number in `text` (outside strings) that
// overflows a double: where nlohmann's out_of_range.406 arose.
std::size_t first_overflowing_number(std::string_view text) {
    bool in_string = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (in_string) {
            if (c == '\\') ++i;
            else if (c == '"') in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '-' || (c >= '0' && c <= '9')) {
            std::size_t end = i;
            while (end < text.size() && std::string_view("0123456789+-.eE").find(text[end]) != std::string_view::npos) ++end;
            const std::string number(text.substr(i, end - i));
            if (!std::isfinite(std::strtod(number.c_str(), nullptr))) return i;
            i = end - 1;
        }
    }
    return text.size();
}

} // namespace

void throw_json_error(const std::exception& e, std::string_view text, const std::string& path) {
    // nlohmann's messages quote the bytes it read last ("last read: '...'",
    // "number overflow parsing '...'"): a file's content never goes to
    // stderr, so we keep only its own words and say where.
    std::size_t at = text.size();
    std::string what;
    if (const auto* p = dynamic_cast<const nlohmann::json::parse_error*>(&e)) {
        at = p->byte > 0 ? std::min<std::size_t>(p->byte - 1, text.size()) : 0; // nlohmann counts from 1
        std::string message = exception_text(e); // "parse error at line L, column C: syntax error while ..."
        const std::size_t colon = message.find(": ");
        what = colon == std::string::npos ? "syntax error" : message.substr(colon + 2);
        if (std::size_t cut = what.find("; last read: '"); cut != std::string::npos) what.resize(cut);
    } else if (const auto* r = dynamic_cast<const nlohmann::json::out_of_range*>(&e); r && r->id == 406) {
        at = first_overflowing_number(text);
        what = "number out of the range of a double";
    } else if (dynamic_cast<const std::bad_alloc*>(&e)) {
        throw Error(path + ": out of memory");
    } else {
        what = "unreadable";
    }
    std::size_t line = 1, line_start = 0;
    for (std::size_t i = 0; i < at; ++i)
        if (text[i] == '\n') ++line, line_start = i + 1;
    throw Error(path + ": not valid JSON at line " + std::to_string(line) + ", column " + std::to_string(at - line_start + 1) + " (byte " +
                std::to_string(at) + "): " + what);
}

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
