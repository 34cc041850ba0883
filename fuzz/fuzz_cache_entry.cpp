// Fuzzes the analysis cache entry reader (pipeline::parse_analysis): an entry
// that fails any structural check is a miss (nullopt), never a crash or an
// allocation beyond its bytes; what reads back keeps the reader's promises
// (vertices finite and within the rect grown by one texel) and reads back
// the same once written again, and reconstruction of a scene of elements
// that use it succeeds or says why, without a crash. The checksum would turn away nearly every
// mutation, so the harness wraps the input in a valid header: bytes 0-1
// are the rect's size, the rest the payload. Seeds: fuzz/corpus/cache_entry/.
#include <cmath>
#include <cstdlib>

#include "depthcull/scene.h"
#include "pipeline/cache.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace depthcull;
    if (size < 2) return 0;
    const Rect rect{7, 3, 1 + data[0] % 64, 1 + data[1] % 64};
    const std::string_view payload(reinterpret_cast<const char*>(data) + 2, size - 2);
    const pipeline::CacheKey key = pipeline::hash_bytes_128(data, 2);
    const std::string entry = pipeline::cache_entry(key, payload);

    const std::optional<ImageAnalysis> a = pipeline::parse_analysis(entry, key, rect);
    if (!a) return 0;
    for (const auto* list : {&a->boundary, &a->opaque})
        for (const Polygon& p : *list)
            for (const Vec2& v : p)
                if (!(v.x >= rect.x - 1 && v.x <= rect.x + rect.w + 1 && v.y >= rect.y - 1 && v.y <= rect.y + rect.h + 1)) std::abort();
    const std::optional<ImageAnalysis> back = pipeline::parse_analysis(pipeline::serialize_analysis(key, *a), key, rect);
    if (!back || back->boundary != a->boundary || back->opaque != a->opaque ||
        back->stats.nontransparent_texels != a->stats.nontransparent_texels || back->stats.boundary_vertices != a->stats.boundary_vertices)
        std::abort();
    // Downstream: what a cache hit feeds (paper 2.3), two overlapping elements.
    Scene scene;
    scene.viewport = {0, 0, 96, 96};
    scene.images.push_back({"fuzz", "fuzz.png", rect.x + rect.w, rect.y + rect.h});
    scene.elements.push_back({0, rect});
    scene.elements.push_back({0, rect, {0.5, 0.5, -0.5, 0.5, 9, 2}});
    SceneMeshes meshes;
    if (reconstruct_scene(scene, {&*a, &*a}, {}, &meshes) != ReconstructStatus::ok) std::abort();
    return 0;
}
