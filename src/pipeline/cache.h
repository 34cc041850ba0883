// Internal to src/pipeline (hashing and orchestration, not a file format):
// the on-disk cache of per-image analyses (issue 4,
// paper section 2 notes the per-image results are reusable across scenes).
//
// One file per entry, named by a 128-bit key of everything the analysis
// depends on: the rect's texel alphas and size, the options, and the format
// version. Entries are written with write_file_atomic (temporary file +
// rename), so concurrent runs and a killed process never leave a partial
// entry under a real name; each entry also carries its key and a checksum
// of its header and payload, and anything that fails to check is recomputed.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "depthcull/analyze.h"

namespace depthcull::pipeline {

// 2: the payload no longer ends with the analysis' wall time (ImageStats
// holds none). 3: the checksum covers the header (magic, version, key,
// size) as well as the payload. 4: the key hashes the texture filter once
// (it was hashed twice, where two copies of it once lived). The version is
// hashed into every key, so an older entry is never even opened.
inline constexpr std::uint32_t kCacheFormatVersion = 4;

// depthcull's directory `what` under the user's cache home:
// $XDG_CACHE_HOME/depthcull/<what>, else ~/.cache/depthcull/<what>; "" when
// neither is set. A relative XDG_CACHE_HOME is invalid and ignored (the XDG
// Base Directory spec): it made a cache under whatever directory a run was
// in. default_cache_dir ("analysis") and default_profile_cache_dir
// ("profiles") are this one rule.
std::string user_cache_dir(const char* what);

struct CacheKey {
    std::array<std::uint64_t, 2> words{};
    std::string hex() const; // 32 hex digits
};

// Two independent 64-bit hashes of the bytes: a 128-bit digest.
CacheKey hash_bytes_128(const void* data, std::size_t size, std::uint64_t seed = 0);

// Key of the analysis of `rect` in `image` with `options`. The rect's
// position is not part of it: equal tiles in different places share.
CacheKey analysis_key(ImageView image, Rect rect, const AnalyzeOptions& options);

// The entry file for a key under `dir`.
std::string cache_entry_path(const std::string& dir, const CacheKey& key);

// Serialized analysis (polygons relative to the rect's origin) and back;
// parse returns nullopt for anything malformed, truncated or mismatched.
std::string serialize_analysis(const CacheKey& key, const ImageAnalysis& analysis);
std::optional<ImageAnalysis> parse_analysis(const std::string& bytes, const CacheKey& key, Rect rect);
// The entry around a payload: magic, version, key, size, payload, checksum
// (serialize_analysis ends with it; the fuzz harness wraps its input in it).
std::string cache_entry(const CacheKey& key, std::string_view payload);

// Reads an entry; nullopt when it is missing or does not check.
std::optional<ImageAnalysis> cache_load(const std::string& dir, const CacheKey& key, Rect rect);
// Writes an entry; returns false (and leaves no partial file) on failure.
bool cache_store(const std::string& dir, const CacheKey& key, const ImageAnalysis& analysis);

} // namespace depthcull::pipeline
