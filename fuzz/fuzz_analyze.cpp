// Fuzzes PNG decoding and the per-image analysis, and checks the two
// guarantees on whatever decodes: boundary polygons contain every
// non-transparent texel, opaque polygons touch no non-opaque texel.
// Seeds: fuzz/corpus/analyze/ (an options byte, then a PNG).
#include <algorithm>
#include <cstdlib>

#include "depthcull/analyze.h"
#include "depthcull/io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 2) return 0;
    // The first byte picks the options, each from its own bits so every
    // method meets every filter: bits 0-3 max_vertices 3..16 (3 is below
    // kMinBoundaryVertices and acts as it), bits 4-5 the opaque method,
    // bit 6 split_parts, bit 7 the filter (AnalyzeOptions::filter, the one
    // filter both stages analyze for).
    const std::uint8_t o = data[0];
    depthcull::AnalyzeOptions options;
    options.boundary.max_vertices = 3 + (o & 15) % 14;
    static constexpr depthcull::OpaqueMethod methods[] = {depthcull::OpaqueMethod::fast, depthcull::OpaqueMethod::paper,
                                                          depthcull::OpaqueMethod::grow, depthcull::OpaqueMethod::fast};
    options.opaque.method = methods[(o >> 4) & 3];
    options.boundary.split_parts = (o & 0x40) != 0;
    const depthcull::Filter filter = (o & 0x80) ? depthcull::Filter::linear : depthcull::Filter::nearest;
    options.filter = filter;
    depthcull::Image image;
    try {
        image = depthcull::io::decode_png(data + 1, size - 1, "fuzz.png");
    } catch (const depthcull::Error&) {
        return 0;
    }
    if (std::int64_t(image.width) * image.height > 256 * 256) return 0; // keep iterations fast
    depthcull::Rect rect = image.view().bounds();
    depthcull::ImageAnalysis a = depthcull::analyze_image(image.view(), rect, options);
    const int max_vertices = std::max(options.boundary.max_vertices, depthcull::kMinBoundaryVertices);
    for (const auto& p : a.boundary)
        if (int(p.size()) > max_vertices || !depthcull::is_simple(p)) std::abort();
    if (depthcull::count_uncontained_texels(image.view(), rect, a.boundary, filter) != 0) std::abort();
    if (depthcull::count_opaque_violations(image.view(), rect, a.opaque, filter) != 0) std::abort();
    return 0;
}
