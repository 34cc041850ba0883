// The analysis cache; see cache.h for the guarantees and why they hold.
// Entry layout (little-endian):
//   "DCAN" u32 version, u64 key[2], u64 payload_size, payload, u64 checksum
// The checksum covers everything before it, the key included: an entry
// copied from another image with its key bytes rewritten does not check.
// payload: i32 rect w, h; polygon lists (boundary, opaque) as u32 count,
// then per polygon u32 n and n (f64 x, f64 y) relative to the rect's
// top-left; then the ImageStats fields.
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "depthcull/io.h"
#include "pipeline/cache.h"

namespace depthcull::pipeline {

namespace {

constexpr char kMagic[4] = {'D', 'C', 'A', 'N'};
constexpr std::uint32_t kMaxCachedVertices = 1u << 20;

std::uint64_t rotl(std::uint64_t x, int r) { return (x << r) | (x >> (64 - r)); }
std::uint64_t fmix(std::uint64_t k) {
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    k *= 0xc4ceb9fe1a85ec53ull;
    k ^= k >> 33;
    return k;
}

// Two lanes with different multipliers and rotations over 8-byte words,
// finalized together: a 128-bit digest. Not cryptographic; collisions of
// random inputs are out of reach, which is what a cache key needs.
class Hasher128 {
public:
    explicit Hasher128(std::uint64_t seed) : h1_(seed ^ 0x9e3779b97f4a7c15ull), h2_(rotl(seed, 32) ^ 0xc2b2ae3d27d4eb4full) {}
    void update(const void* data, std::size_t size) {
        const auto* p = static_cast<const unsigned char*>(data);
        total_ += size;
        while (size > 0) {
            std::size_t take = std::min<std::size_t>(8 - fill_, size);
            std::memcpy(buffer_ + fill_, p, take);
            fill_ += take;
            p += take;
            size -= take;
            if (fill_ == 8) word();
        }
    }
    template <class T>
    void value(const T& v) { update(&v, sizeof v); }
    CacheKey finish() {
        std::uint64_t pad = fill_;
        while (fill_ != 0) update("", 1); // zero padding of the last word
        std::uint64_t a = h1_ ^ total_ ^ pad, b = h2_ ^ (total_ * 0x9e3779b97f4a7c15ull);
        a += b;
        b += a;
        a = fmix(a);
        b = fmix(b);
        a += b;
        b += a;
        return {{a, b}};
    }

private:
    void word() {
        std::uint64_t w;
        std::memcpy(&w, buffer_, 8);
        h1_ = rotl(h1_ ^ (w * 0x87c37b91114253d5ull), 31) * 5 + 0x52dce729;
        h2_ = (rotl(h2_ + w * 0x4cf5ad432745937full, 27) ^ h1_) * 0x9e3779b97f4a7c15ull + 0x38495ab5;
        fill_ = 0;
    }
    std::uint64_t h1_, h2_, total_ = 0;
    unsigned char buffer_[8] = {};
    std::size_t fill_ = 0;
};

class Writer {
public:
    template <class T>
    void put(const T& v) { bytes.append(reinterpret_cast<const char*>(&v), sizeof v); }
    void polygons(const std::vector<Polygon>& list, Rect rect) {
        put(std::uint32_t(list.size()));
        for (const Polygon& p : list) {
            put(std::uint32_t(p.size()));
            for (const Vec2& v : p) {
                put(v.x - rect.x);
                put(v.y - rect.y);
            }
        }
    }
    std::string bytes;
};

class Reader {
public:
    explicit Reader(std::string_view b) : bytes_(b) {}
    template <class T>
    bool get(T& v) {
        if (bytes_.size() - pos_ < sizeof v) return false;
        std::memcpy(&v, bytes_.data() + pos_, sizeof v);
        pos_ += sizeof v;
        return true;
    }
    // Structural checks beyond the checksum (an entry can be damaged
    // before it is summed, or collide): every count fits in the bytes
    // left, so nothing is allocated for data that is not there, and every
    // vertex is finite and within the rect grown by one texel (linear
    // filtering's half-texel margin, with room to spare); every polygon has
    // 3 vertices at least, as the analysis makes them. The vertex total is
    // summed in 64 bits: 32 would wrap past the limit.
    bool polygons(std::vector<Polygon>& list, Rect rect) {
        std::uint32_t count = 0;
        std::uint64_t total = 0;
        if (!get(count) || count > kMaxCachedVertices || count > left() / sizeof(std::uint32_t)) return false;
        list.resize(count);
        for (Polygon& p : list) {
            std::uint32_t n = 0;
            if (!get(n) || n < 3 || (total += n) > kMaxCachedVertices || n > left() / (2 * sizeof(double))) return false;
            p.resize(n);
            for (Vec2& v : p) {
                if (!get(v.x) || !get(v.y)) return false;
                if (!(v.x >= -1 && v.x <= rect.w + 1 && v.y >= -1 && v.y <= rect.h + 1)) return false; // false for nan
                v.x += rect.x;
                v.y += rect.y;
            }
        }
        return true;
    }
    std::size_t left() const { return bytes_.size() - pos_; }
    bool done() const { return pos_ == bytes_.size(); }

private:
    std::string_view bytes_;
    std::size_t pos_ = 0;
};

} // namespace

std::string CacheKey::hex() const {
    static const char digits[] = "0123456789abcdef";
    std::string s;
    for (std::uint64_t w : words)
        for (int shift = 60; shift >= 0; shift -= 4) s += digits[(w >> shift) & 15];
    return s;
}

CacheKey hash_bytes_128(const void* data, std::size_t size, std::uint64_t seed) {
    Hasher128 h(seed);
    h.update(data, size);
    return h.finish();
}

CacheKey analysis_key(ImageView image, Rect rect, const AnalyzeOptions& o) {
    Hasher128 h(0x6465707468637563ull); // "depthcuc"
    h.value(kCacheFormatVersion);
    h.value(std::int32_t(kAnalysisVersion)); // a newer algorithm never reads an older one's results
    h.value(std::int32_t(rect.w));
    h.value(std::int32_t(rect.h));
    h.value(std::int32_t(o.boundary.max_vertices));
    h.value(std::int32_t(o.filter));
    h.value(std::int32_t(o.boundary.split_parts));
    h.value(std::int32_t(o.opaque.method));
    h.value(std::int32_t(o.opaque.max_polygons));
    h.value(o.opaque.min_coverage);
    h.value(std::int32_t(o.opaque.min_area));
    // Only alpha: both stages see texels only through their alpha classes
    // (paper 2.1, 2.2), so a recoloured sprite shares its entry.
    std::vector<std::uint8_t> row(std::size_t(rect.w));
    for (int y = rect.y; y < rect.y + rect.h; ++y) {
        for (int x = 0; x < rect.w; ++x) row[std::size_t(x)] = image.alpha(rect.x + x, y);
        h.update(row.data(), row.size());
    }
    return h.finish();
}

std::string cache_entry_path(const std::string& dir, const CacheKey& key) {
    std::string hex = key.hex();
    // Two-digit fan-out keeps directories small for large corpora.
    return (std::filesystem::path(dir) / hex.substr(0, 2) / (hex.substr(2) + ".dca")).string();
}

std::string serialize_analysis(const CacheKey& key, const ImageAnalysis& a) {
    Writer payload;
    payload.put(std::int32_t(a.rect.w));
    payload.put(std::int32_t(a.rect.h));
    payload.polygons(a.boundary, a.rect);
    payload.polygons(a.opaque, a.rect);
    const ImageStats& s = a.stats;
    payload.put(std::int64_t(s.nontransparent_texels));
    payload.put(std::int64_t(s.opaque_texels));
    payload.put(s.boundary_area);
    payload.put(s.bbox_area);
    payload.put(std::int32_t(s.boundary_vertices));
    payload.put(s.opaque_area);
    payload.put(std::int64_t(s.opaque_covered_texels));
    payload.put(s.opaque_coverage);
    return cache_entry(key, payload.bytes);
}

std::string cache_entry(const CacheKey& key, std::string_view payload) {
    Writer entry;
    entry.bytes.append(kMagic, 4);
    entry.put(kCacheFormatVersion);
    entry.put(key.words[0]);
    entry.put(key.words[1]);
    entry.put(std::uint64_t(payload.size()));
    entry.bytes += payload;
    entry.put(hash_bytes_128(entry.bytes.data(), entry.bytes.size(), 1).words[0]);
    return std::move(entry.bytes);
}

std::optional<ImageAnalysis> parse_analysis(const std::string& bytes, const CacheKey& key, Rect rect) {
    if (bytes.size() < 4 || std::memcmp(bytes.data(), kMagic, 4) != 0) return std::nullopt;
    Reader header(std::string_view(bytes).substr(4));
    std::uint32_t version = 0;
    std::uint64_t k0 = 0, k1 = 0, size = 0;
    if (!header.get(version) || !header.get(k0) || !header.get(k1) || !header.get(size)) return std::nullopt;
    const std::size_t header_size = 4 + 4 + 8 + 8 + 8;
    if (version != kCacheFormatVersion || k0 != key.words[0] || k1 != key.words[1]) return std::nullopt;
    if (size > bytes.size() || bytes.size() != header_size + size + 8) return std::nullopt;
    std::string_view payload(bytes.data() + header_size, std::size_t(size));
    std::uint64_t checksum = 0;
    std::memcpy(&checksum, bytes.data() + header_size + size, 8);
    if (checksum != hash_bytes_128(bytes.data(), header_size + size, 1).words[0]) return std::nullopt;

    Reader r(payload);
    ImageAnalysis a;
    a.rect = rect;
    std::int32_t w = 0, h = 0, vertices = 0;
    std::int64_t nontransparent = 0, opaque = 0, covered = 0;
    ImageStats& s = a.stats;
    if (!r.get(w) || !r.get(h) || w != rect.w || h != rect.h) return std::nullopt;
    if (!r.polygons(a.boundary, rect) || !r.polygons(a.opaque, rect)) return std::nullopt;
    if (!r.get(nontransparent) || !r.get(opaque) || !r.get(s.boundary_area) || !r.get(s.bbox_area) || !r.get(vertices) ||
        !r.get(s.opaque_area) || !r.get(covered) || !r.get(s.opaque_coverage) || !r.done())
        return std::nullopt;
    // Counts within the rect, areas and fractions finite and sane.
    const std::int64_t texels = std::int64_t(w) * h;
    auto count_ok = [&](std::int64_t c) { return c >= 0 && c <= texels; };
    auto area_ok = [&](double a) { return a >= 0 && a <= double(rect.w + 2) * double(rect.h + 2); }; // false for nan
    if (!count_ok(nontransparent) || !count_ok(opaque) || !count_ok(covered) || covered > opaque || vertices < 0 ||
        vertices > std::int32_t(kMaxCachedVertices) || !area_ok(s.boundary_area) || !area_ok(s.bbox_area) || !area_ok(s.opaque_area) ||
        !(s.opaque_coverage >= 0 && s.opaque_coverage <= 1))
        return std::nullopt;
    s.nontransparent_texels = nontransparent;
    s.opaque_texels = opaque;
    s.boundary_vertices = vertices;
    s.opaque_covered_texels = covered;
    return a;
}

std::string user_cache_dir(const char* what) {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg == '/') return (std::filesystem::path(xdg) / "depthcull" / what).string();
    if (const char* home = std::getenv("HOME"); home && *home) return (std::filesystem::path(home) / ".cache" / "depthcull" / what).string();
    return {};
}

std::optional<ImageAnalysis> cache_load(const std::string& dir, const CacheKey& key, Rect rect) {
    std::string path = cache_entry_path(dir, key);
    std::error_code ec;
    // Entries are files this code wrote: a link (which could point at any
    // file), a FIFO (which would block the read) or anything else is a miss,
    // and cache_store replaces it.
    if (!std::filesystem::is_regular_file(std::filesystem::symlink_status(path, ec))) return std::nullopt;
    try {
        return parse_analysis(io::read_file(path), key, rect);
    } catch (const depthcull::Error&) {
        return std::nullopt; // unreadable: recompute
    }
}

bool cache_store(const std::string& dir, const CacheKey& key, const ImageAnalysis& analysis) {
    std::string path = cache_entry_path(dir, key);
    std::error_code ec;
    std::filesystem::create_directories(std::filesystem::path(path).parent_path(), ec);
    if (ec) return false;
    // write_file_atomic writes an output through a link and into a FIFO in
    // place, as a user asking for one means; an entry is never a link or a
    // FIFO of the user's, so one there is removed (the link, not what it
    // points at): a link planted in the cache replaced its target, the scene
    // itself included, and a FIFO blocked the run.
    const std::filesystem::file_status st = std::filesystem::symlink_status(path, ec);
    if (std::filesystem::is_directory(st)) return false;
    if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st) && !std::filesystem::remove(path, ec)) return false;
    try {
        io::write_file_atomic(path, serialize_analysis(key, analysis));
        return true;
    } catch (const depthcull::Error&) {
        return false; // a cache that cannot be written only costs time
    }
}


} // namespace depthcull::pipeline
