#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include <nlohmann/json.hpp>

#include "depthcull/limits.h"
#include "io/formats.h"

namespace depthcull::io {

namespace {

// What glibc's malloc takes for a request of n bytes: n and its 8-byte
// header rounded up to 16, at least 32.
constexpr std::uint64_t chunk(std::uint64_t n) { return std::max<std::uint64_t>(32, (n + 8 + 15) & ~std::uint64_t(15)); }

// Heap bytes of a std::string of `length` characters beyond its object:
// none within the small-string buffer (15 characters).
constexpr std::uint64_t string_heap(std::uint64_t length) { return length > 15 ? chunk(length + 1) : 0; }

std::string mib(std::uint64_t bytes) { return std::to_string((bytes + (std::uint64_t(1) << 20) - 1) >> 20); }

[[noreturn]] void too_large(const char* kind, std::uint64_t bytes, const std::string& path) {
    throw Error(path + ": the " + kind + " document would take about " + mib(bytes) + " MiB of memory once parsed, more than the " +
                mib(limits::kMaxDocumentBytes) + " MiB (kMaxDocumentBytes)");
}

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

// nlohmann::json's layout (16-byte values; arrays a heap std::vector of
// values, objects a heap std::map whose nodes hold key and value, strings
// a heap std::string) priced at malloc's chunk sizes; an array's buffer
// grows by doubling, so a value in it is priced at twice its size. 24 MiB
// of "[]," measured 570 MB once parsed (less the text), estimated 537 MB.
// The pass also checks nesting, so the stack of container kinds is bounded.
std::uint64_t json_document_bytes(std::string_view text, const std::string& path) {
    constexpr std::uint64_t kValue = 32;                      // a 16-byte value in its array's buffer, which grows by doubling
    constexpr std::uint64_t kArray = chunk(24);               // the std::vector behind an array
    constexpr std::uint64_t kObject = chunk(48);              // the std::map behind an object
    constexpr std::uint64_t kMember = chunk(32 + 32 + 16);    // a map node: links, key, value
    constexpr std::uint64_t kString = chunk(32);              // the std::string behind a string
    bool in_object[limits::kMaxNestingDepth + 1] = {};
    int depth = 0;
    bool key_next = false; // in an object, the next string is a member's key
    std::uint64_t bytes = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        const bool member_slot = depth > 0 && in_object[depth];
        if (c == '"') {
            std::size_t start = i + 1;
            for (++i; i < text.size() && text[i] != '"'; ++i)
                if (text[i] == '\\') ++i;
            const std::uint64_t length = std::min(i, text.size()) - start; // escapes counted as written: about
            if (key_next) {
                bytes += kMember + string_heap(length);
                key_next = false;
            } else {
                bytes += (member_slot ? 0 : kValue) + kString + string_heap(length);
            }
        } else if (c == '[' || c == '{') {
            if (++depth > limits::kMaxNestingDepth)
                throw Error(path + ": JSON nested deeper than " + std::to_string(limits::kMaxNestingDepth) + " levels at byte " +
                            std::to_string(i) + " (kMaxNestingDepth)");
            bytes += (member_slot ? 0 : kValue) + (c == '[' ? kArray : kObject);
            in_object[depth] = c == '{';
            key_next = c == '{';
        } else if (c == ']' || c == '}') {
            if (depth > 0) --depth;
            key_next = false;
        } else if (c == ',') {
            key_next = member_slot;
        } else if (!member_slot && (c == '-' || (c >= '0' && c <= '9') || c == 't' || c == 'f' || c == 'n')) {
            // A number or literal in an array: its slot (a member's is in
            // its node). Skip the rest of the token.
            bytes += kValue;
            while (i + 1 < text.size() && text[i + 1] != ',' && text[i + 1] != ']' && text[i + 1] != '}' && text[i + 1] != ' ' &&
                   text[i + 1] != '\n' && text[i + 1] != '\t' && text[i + 1] != '\r')
                ++i;
        }
    }
    return bytes;
}

// pugixml's layout: the text copied once (strings stay in place), 64 bytes
// per node (element, text, CDATA) and 40 per attribute, in pages. Parsed
// with pugi::parse_default: comments, declarations, processing
// instructions and whitespace-only text make no node.
std::uint64_t xml_document_bytes(std::string_view text) {
    constexpr std::uint64_t kNode = 64, kAttribute = 40;
    std::uint64_t bytes = text.size() + kNode;
    auto skip_past = [&](std::size_t from, std::string_view end) {
        std::size_t at = text.find(end, from);
        return at == std::string_view::npos ? text.size() : at + end.size();
    };
    std::size_t i = 0;
    while (i < text.size()) {
        if (text[i] != '<') {
            const std::size_t end = std::min(text.find('<', i), text.size());
            for (std::size_t k = i; k < end; ++k)
                if (text[k] != ' ' && text[k] != '\t' && text[k] != '\n' && text[k] != '\r') {
                    bytes += kNode;
                    break;
                }
            i = end;
        } else if (text.compare(i, 4, "<!--") == 0) {
            i = skip_past(i + 4, "-->");
        } else if (text.compare(i, 9, "<![CDATA[") == 0) {
            bytes += kNode;
            i = skip_past(i + 9, "]]>");
        } else if (text.compare(i, 2, "<?") == 0) {
            i = skip_past(i + 2, "?>");
        } else if (text.compare(i, 2, "<!") == 0 || text.compare(i, 2, "</") == 0) {
            i = skip_past(i + 2, ">");
        } else {
            bytes += kNode;
            char quote = 0;
            for (++i; i < text.size(); ++i) {
                const char c = text[i];
                if (quote) {
                    if (c == quote) quote = 0;
                } else if (c == '"' || c == '\'') {
                    quote = c;
                } else if (c == '=') {
                    bytes += kAttribute;
                } else if (c == '>') {
                    break;
                }
            }
            ++i;
        }
    }
    return bytes;
}

void check_json_document(std::string_view text, const std::string& path) {
    if (std::uint64_t bytes = json_document_bytes(text, path); bytes > limits::kMaxDocumentBytes) too_large("JSON", bytes, path);
}

void check_xml_document(std::string_view text, const std::string& path) {
    if (std::uint64_t bytes = xml_document_bytes(text); bytes > limits::kMaxDocumentBytes) too_large("XML", bytes, path);
}

void check_documents_held(std::uint64_t bytes, const std::string& path) {
    if (bytes > limits::kMaxDocumentBytes)
        throw Error(path + ": with the documents read before it, the parsed documents would take about " + mib(bytes) +
                    " MiB of memory, more than the " + mib(limits::kMaxDocumentBytes) + " MiB (kMaxDocumentBytes)");
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
