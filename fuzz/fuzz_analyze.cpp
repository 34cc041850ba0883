// Fuzzes PNG decoding and the per-image analysis, and checks the two
// guarantees on whatever decodes: boundary polygons contain every
// non-transparent texel, opaque polygons touch no non-opaque texel.
#include <cstdlib>

#include "depthcull/analyze.h"
#include "depthcull/io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 2) return 0;
    // First byte picks options, the rest is the PNG.
    depthcull::AnalyzeOptions options;
    options.boundary.max_vertices = 3 + data[0] % 14;
    options.filter = (data[0] & 0x80) ? depthcull::Filter::linear : depthcull::Filter::nearest;
    options.opaque.method = (data[0] & 0x40) ? depthcull::OpaqueMethod::paper : (data[0] & 0x80) ? depthcull::OpaqueMethod::grow : depthcull::OpaqueMethod::fast;
    depthcull::Image image;
    try {
        image = depthcull::io::decode_png(data + 1, size - 1, "fuzz.png");
    } catch (const depthcull::io::Error&) {
        return 0;
    }
    if (std::int64_t(image.width) * image.height > 256 * 256) return 0; // keep iterations fast
    depthcull::Rect rect = image.view().bounds();
    depthcull::ImageAnalysis a = depthcull::analyze_image(image.view(), rect, options);
    for (const auto& p : a.boundary)
        if (int(p.size()) > options.boundary.max_vertices || !depthcull::is_simple(p)) std::abort();
    if (depthcull::count_uncontained_texels(image.view(), rect, a.boundary, options.filter) != 0) std::abort();
    if (depthcull::count_opaque_violations(image.view(), rect, a.opaque, options.filter) != 0) std::abort();
    return 0;
}
