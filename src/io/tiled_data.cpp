// Tiled layer data: the cell grids of tile layers in every encoding Tiled
// writes (CSV, base64 with no / zlib / gzip / zstd compression, and the old
// XML <tile gid> form), and the chunks of infinite maps.
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cstring>

#include <sys/stat.h>

#include "depthcull/limits.h"
#include "io/tiled_internal.h"

namespace depthcull::io::tiled {

namespace {

bool is_space(char c) { return c == ' ' || c == '\n' || c == '\r' || c == '\t'; }

int base64_value(char c) {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
}

std::string attr_text(pugi::xml_node node, const char* name) { return node.attribute(name).as_string(); }

std::vector<std::uint32_t> parse_csv(std::string_view text, std::size_t count, const std::string& where) {
    std::vector<std::uint32_t> gids;
    gids.reserve(count);
    std::size_t i = 0, n = text.size();
    while (true) {
        while (i < n && is_space(text[i])) ++i;
        if (i == n) break;
        std::uint32_t value = 0;
        auto [end, ec] = std::from_chars(text.data() + i, text.data() + n, value);
        if (ec != std::errc())
            // Says what, not the bytes: a file's content never goes to stderr
            // (it may hold anything, newlines included).
            throw Error(where + ": bad CSV data at cell " + std::to_string(gids.size()) + " (not a gid: a whole number 0..4294967295)");
        if (gids.size() == count) throw Error(where + ": CSV data has more than the expected " + std::to_string(count) + " cells");
        gids.push_back(value);
        i = std::size_t(end - text.data());
        while (i < n && is_space(text[i])) ++i;
        if (i < n && text[i] == ',') ++i;
        else if (i < n) throw Error(where + ": bad CSV data after cell " + std::to_string(gids.size()));
    }
    if (gids.size() != count)
        throw Error(where + ": CSV data has " + std::to_string(gids.size()) + " cells, expected " + std::to_string(count));
    return gids;
}

// A zstd stream -> bytes, streamed so a frame claiming a huge size
// allocates nothing beyond max_bytes (Tiled writes single frames, but
// concatenated frames are valid zstd too).
std::string unzstd_bytes(std::string_view data, std::size_t max_bytes, const std::string& where) {
    ZSTD_DCtx* z = ZSTD_createDCtx();
    if (!z) throw Error(where + ": zstd initialisation failed");
    std::string out;
    char buffer[65536];
    ZSTD_inBuffer in{data.data(), data.size(), 0};
    std::size_t last = 0;
    while (true) {
        ZSTD_outBuffer o{buffer, sizeof buffer, 0};
        last = ZSTD_decompressStream(z, &o, &in);
        if (ZSTD_isError(last)) {
            std::string message = ZSTD_getErrorName(last);
            ZSTD_freeDCtx(z);
            throw Error(where + ": corrupt zstd data (" + message + ")");
        }
        if (out.size() + o.pos > max_bytes) {
            ZSTD_freeDCtx(z);
            throw Error(where + ": decompressed data is larger than the expected " + std::to_string(max_bytes - 1) + " bytes");
        }
        out.append(buffer, o.pos);
        if (in.pos == in.size && o.pos < o.size) break;
    }
    ZSTD_freeDCtx(z);
    if (last != 0) throw Error(where + ": corrupt zstd data (truncated)");
    return out;
}

// The cells of one <data> or <chunk> node: `count` gids.
std::vector<std::uint32_t> decode_cells(pugi::xml_node node, const std::string& encoding, const std::string& compression,
                                        std::size_t count, const std::string& where) {
    if (encoding.empty()) {
        if (!compression.empty()) throw Error(where + ": compression '" + compression + "' without an encoding");
        std::vector<std::uint32_t> gids;
        gids.reserve(count);
        for (pugi::xml_node tile : node.children("tile")) {
            if (gids.size() == count) throw Error(where + ": more than the expected " + std::to_string(count) + " <tile> cells");
            gids.push_back(gid_attr(tile, "gid", where));
        }
        if (gids.size() != count)
            throw Error(where + ": " + std::to_string(gids.size()) + " <tile> cells, expected " + std::to_string(count));
        return gids;
    }
    if (encoding == "csv") {
        if (!compression.empty()) throw Error(where + ": compression '" + compression + "' with CSV encoding");
        return parse_csv(node.text().get(), count, where);
    }
    if (encoding != "base64") throw Error(where + ": unsupported encoding '" + encoding + "'");
    std::vector<std::uint8_t> raw = decode_base64(node.text().get(), where);
    std::string bytes;
    if (compression.empty()) {
        bytes.assign(raw.begin(), raw.end());
    } else if (compression == "zlib" || compression == "gzip") {
        bytes = inflate_bytes(std::string_view(reinterpret_cast<const char*>(raw.data()), raw.size()), count * 4 + 1, where);
    } else if (compression == "zstd") {
        bytes = unzstd_bytes(std::string_view(reinterpret_cast<const char*>(raw.data()), raw.size()), count * 4 + 1, where);
    } else {
        throw Error(where + ": unsupported compression '" + compression + "'");
    }
    if (bytes.size() != count * 4)
        throw Error(where + ": data has " + std::to_string(bytes.size()) + " bytes, expected " + std::to_string(count * 4) +
                    " (" + std::to_string(count) + " cells)");
    std::vector<std::uint32_t> gids(count);
    for (std::size_t k = 0; k < count; ++k) {
        const auto* b = reinterpret_cast<const unsigned char*>(bytes.data()) + 4 * k;
        gids[k] = std::uint32_t(b[0]) | std::uint32_t(b[1]) << 8 | std::uint32_t(b[2]) << 16 | std::uint32_t(b[3]) << 24;
    }
    return gids;
}

std::size_t checked_cells(int width, int height, const std::string& where) {
    if (width <= 0 || height <= 0 || std::int64_t(width) * height > kMaxCells)
        throw Error(where + ": layer size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1.." +
                    std::to_string(kMaxCells) + " cells (kMaxLayerCells)");
    return std::size_t(width) * std::size_t(height);
}

} // namespace

namespace {

// The whole value as a T, else an Error naming the attribute.
template <typename T>
T parse_attr(pugi::xml_attribute a, const char* name, const std::string& where, const char* what) {
    std::string_view text = a.value();
    T value{};
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size() || text.empty())
        throw Error(where + ": attribute " + name + "=\"" + std::string(text.substr(0, 64)) + "\" is not " + what);
    return value;
}

} // namespace

int int_attr(pugi::xml_node node, const char* name, int fallback, const std::string& where) {
    pugi::xml_attribute a = node.attribute(name);
    return a ? parse_attr<int>(a, name, where, "an integer") : fallback;
}

long long llong_attr(pugi::xml_node node, const char* name, long long fallback, const std::string& where) {
    pugi::xml_attribute a = node.attribute(name);
    return a ? parse_attr<long long>(a, name, where, "an integer") : fallback;
}

std::uint32_t gid_attr(pugi::xml_node node, const char* name, const std::string& where) {
    pugi::xml_attribute a = node.attribute(name);
    return a ? parse_attr<std::uint32_t>(a, name, where, "a tile gid (0..4294967295)") : 0;
}

double double_attr(pugi::xml_node node, const char* name, double fallback, const std::string& where) {
    pugi::xml_attribute a = node.attribute(name);
    return a ? parse_attr<double>(a, name, where, "a number") : fallback;
}

bool visible_attr(pugi::xml_node node, const std::string& where) { return int_attr(node, "visible", 1, where) != 0; }

std::string inflate_bytes(std::string_view data, std::size_t max_bytes, const std::string& where, bool gzip_members) {
    z_stream z;
    std::memset(&z, 0, sizeof z);
    // 15 + 32: accept both zlib and gzip headers, as Tiled's own reader does.
    if (inflateInit2(&z, 15 + 32) != Z_OK) throw Error(where + ": zlib initialisation failed");
    std::string out;
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    z.avail_in = uInt(std::min<std::size_t>(data.size(), UINT_MAX));
    char buffer[1 << 16];
    int status = Z_OK;
    for (;;) {
        if (status == Z_STREAM_END) {
            // A gzip file may hold several members, one after the other,
            // whose contents gunzip joins (`cat a.gz b.gz`); the first was
            // all that was read, and the map was refused as cut short.
            if (!gzip_members || z.avail_in < 2 || z.next_in[0] != 0x1f || z.next_in[1] != 0x8b) break;
            if (inflateReset(&z) != Z_OK) {
                inflateEnd(&z);
                throw Error(where + ": zlib reset failed");
            }
        }
        z.next_out = reinterpret_cast<Bytef*>(buffer);
        z.avail_out = sizeof buffer;
        status = inflate(&z, Z_NO_FLUSH);
        if (status != Z_OK && status != Z_STREAM_END) {
            inflateEnd(&z);
            throw Error(where + ": corrupt compressed data (" + (z.msg ? z.msg : "truncated") + ")");
        }
        out.append(buffer, sizeof buffer - z.avail_out);
        if (out.size() > max_bytes) {
            inflateEnd(&z);
            throw Error(where + ": decompressed data is larger than the expected " + std::to_string(max_bytes) + " bytes");
        }
        if (status == Z_OK && z.avail_in == 0 && z.avail_out != 0) {
            inflateEnd(&z);
            throw Error(where + ": corrupt compressed data (truncated)");
        }
    }
    inflateEnd(&z);
    return out;
}

std::string file_identity(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) return "?" + path; // never a device:inode
    return std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
}

std::string maybe_gunzip(std::string_view bytes, const std::string& path) {
    if (bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f && static_cast<unsigned char>(bytes[1]) == 0x8b)
        return inflate_bytes(bytes, kMaxXmlBytes, path, true);
    return std::string(bytes);
}

std::string read_maybe_gzipped(const std::string& path) { return maybe_gunzip(read_file(path), path); }

std::vector<std::uint8_t> decode_base64(std::string_view text, const std::string& where) {
    std::vector<std::uint8_t> out;
    out.reserve(text.size() / 4 * 3);
    std::uint32_t acc = 0;
    int bits = 0, digits = 0, padding = 0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        char c = text[i];
        if (is_space(c)) continue;
        if (c == '=') {
            ++padding;
            continue;
        }
        int v = base64_value(c);
        if (v < 0 || padding > 0)
            throw Error(where + ": bad base64 data at character " + std::to_string(i) + " ('" + std::string(1, c) + "')");
        acc = (acc << 6) | std::uint32_t(v);
        bits += 6;
        ++digits;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(std::uint8_t(acc >> bits));
            acc &= (1u << bits) - 1;
        }
    }
    // A group of 4 characters carries 3 bytes; 1 leftover digit cannot
    // encode a byte, and padding must complete the last group.
    if (digits % 4 == 1 || padding > 2 || (padding > 0 && (digits + padding) % 4 != 0))
        throw Error(where + ": bad base64 data (truncated)");
    return out;
}

CellGrid read_layer_data(pugi::xml_node layer, int width, int height, bool infinite, const std::string& where) {
    pugi::xml_node data = layer.child("data");
    CellGrid grid;
    if (!data) {
        // A layer with no data is empty (Tiled writes none for an empty infinite layer).
        return grid;
    }
    std::string encoding = attr_text(data, "encoding");
    std::string compression = attr_text(data, "compression");
    if (!data.child("chunk")) {
        if (infinite) return grid;
        grid.width = width;
        grid.height = height;
        grid.gids = decode_cells(data, encoding, compression, checked_cells(width, height, where), where);
        return grid;
    }
    // Chunks of an infinite map: merge into their bounding grid so the
    // layer draws like a finite one (Tiled's render order runs across chunks).
    struct Chunk {
        int x, y, w, h;
        std::vector<std::uint32_t> gids;
    };
    std::vector<Chunk> chunks;
    std::int64_t x0 = INT_MAX, y0 = INT_MAX, x1 = INT_MIN, y1 = INT_MIN;
    std::int64_t total = 0; // cells decoded: overlapping chunks each count
    for (pugi::xml_node node : data.children("chunk")) {
        Chunk c;
        std::string here = where + ": chunk " + std::to_string(chunks.size());
        c.x = int_attr(node, "x", 0, here);
        c.y = int_attr(node, "y", 0, here);
        c.w = int_attr(node, "width", 0, here);
        c.h = int_attr(node, "height", 0, here);
        // Cell coordinates stay within +-kMaxMapSide, so every sum and
        // product of them below (and in the placement) fits.
        constexpr int side = limits::kMaxMapSide;
        if (c.x < -side || c.y < -side || c.x > side || c.y > side || c.w > side || c.h > side ||
            c.x + std::int64_t(c.w) > side || c.y + std::int64_t(c.h) > side)
            throw Error(here + ": chunk " + std::to_string(c.x) + "," + std::to_string(c.y) + " " + std::to_string(c.w) + "x" +
                        std::to_string(c.h) + " lies outside +-" + std::to_string(side) + " cells (kMaxMapSide)");
        total += std::int64_t(checked_cells(c.w, c.h, here));
        // 64 overlapping 4096x4096 chunks (23 KB gzipped) reached 4.2 GB.
        if (total > kMaxCells)
            throw Error(here + ": the layer's chunks hold more than " + std::to_string(kMaxCells) + " cells (kMaxLayerCells)");
        c.gids = decode_cells(node, encoding, compression, std::size_t(c.w) * std::size_t(c.h), here);
        x0 = std::min<std::int64_t>(x0, c.x);
        y0 = std::min<std::int64_t>(y0, c.y);
        x1 = std::max<std::int64_t>(x1, std::int64_t(c.x) + c.w);
        y1 = std::max<std::int64_t>(y1, std::int64_t(c.y) + c.h);
        chunks.push_back(std::move(c));
    }
    if (x1 - x0 > INT_MAX || y1 - y0 > INT_MAX || (x1 - x0) * (y1 - y0) > kMaxCells)
        throw Error(where + ": chunks span more than " + std::to_string(kMaxCells) + " cells (kMaxLayerCells)");
    grid.x0 = int(x0);
    grid.y0 = int(y0);
    grid.width = int(x1 - x0);
    grid.height = int(y1 - y0);
    grid.gids.assign(std::size_t(grid.width) * std::size_t(grid.height), 0);
    for (const Chunk& c : chunks)
        for (int r = 0; r < c.h; ++r)
            std::copy_n(c.gids.begin() + std::ptrdiff_t(r) * c.w, c.w,
                        grid.gids.begin() + std::ptrdiff_t(c.y - grid.y0 + r) * grid.width + (c.x - grid.x0));
    return grid;
}

} // namespace depthcull::io::tiled
