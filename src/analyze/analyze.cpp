// Per-image analysis: paper 2.1 (boundary polygons) and 2.2 (opaque
// polygons) for one image or sub-rectangle, with the analyzer's figures.
#include "depthcull/analyze.h"

#include <algorithm>
#include <new>

namespace depthcull {

namespace {

struct TexelCounts {
    std::int64_t nontransparent = 0, opaque = 0;
    int x0 = 0, y0 = 0, x1 = -1, y1 = -1; // bounding box of non-transparent texels, inclusive
};

TexelCounts count_texels(ImageView image, Rect rect) {
    TexelCounts c;
    c.x0 = rect.w;
    c.y0 = rect.h;
    for (int y = 0; y < rect.h; ++y) {
        const std::uint8_t* row = image.texel(rect.x, rect.y + y);
        for (int x = 0; x < rect.w; ++x) {
            std::uint8_t a = row[x * 4 + 3];
            if (is_transparent(a)) continue;
            ++c.nontransparent;
            c.opaque += is_opaque(a);
            c.x0 = std::min(c.x0, x);
            c.x1 = std::max(c.x1, x);
            c.y0 = std::min(c.y0, y);
            c.y1 = std::max(c.y1, y);
        }
    }
    return c;
}

} // namespace

bool edges_bleed(ImageView image, Rect rect) {
    if (rect.empty() || !image.contains(rect)) return false;
    const int x0 = rect.x, y0 = rect.y, x1 = rect.x + rect.w - 1, y1 = rect.y + rect.h - 1; // inclusive
    auto visible = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < image.width && y < image.height && !is_transparent(image.alpha(x, y));
    };
    // The rect's border (d = 0) and the ring around it (d = 1).
    for (int d = 0; d <= 1; ++d) {
        for (int x = x0 - d; x <= x1 + d; ++x)
            if (visible(x, y0 - d) || visible(x, y1 + d)) return true;
        for (int y = y0 - d; y <= y1 + d; ++y)
            if (visible(x0 - d, y) || visible(x1 + d, y)) return true;
    }
    return false;
}

ImageAnalysis analyze_image(ImageView image, Rect rect, const AnalyzeOptions& options) {
    ImageAnalysis result;
    result.rect = rect;
    if (rect.empty() || !image.contains(rect)) return result;

    result.boundary = generate_boundary_polygons(image, rect, options.boundary, options.filter);
    result.opaque = generate_opaque_polygons(image, rect, options.opaque, options.filter);
    result.bleeding_edges = edges_bleed(image, rect);

    TexelCounts counts = count_texels(image, rect);
    ImageStats& s = result.stats;
    s.nontransparent_texels = counts.nontransparent;
    s.opaque_texels = counts.opaque;
    s.bbox_area = counts.x1 < 0 ? 0.0 : double(counts.x1 - counts.x0 + 1) * double(counts.y1 - counts.y0 + 1);
    s.boundary_area = total_area(result.boundary);
    for (const auto& p : result.boundary) s.boundary_vertices += int(p.size());
    s.opaque_area = total_area(result.opaque);
    s.opaque_covered_texels = count_covered_opaque_texels(image, rect, result.opaque);
    s.opaque_coverage = counts.opaque ? double(s.opaque_covered_texels) / double(counts.opaque) : 0.0;
    return result;
}

std::uint64_t analysis_scratch_bytes(Rect rect, const AnalyzeOptions& options) {
    if (rect.empty()) return 0;
    const std::uint64_t texels = std::uint64_t(rect.w) * std::uint64_t(rect.h);
    // Bytes per texel measured on fully opaque images (the worst case) from
    // 2048^2 to 8192^2 (peak resident size less the decoded image), rounded
    // up: the boundary stage's masks; the safe mask with its row and column
    // sums (the paper's search); the growth's own grids; both for fast.
    std::uint64_t per_texel = 2;
    std::uint64_t extra = 0;
    if (options.opaque.max_polygons > 0) switch (options.opaque.method) {
        case OpaqueMethod::paper: per_texel += 12; break;
        case OpaqueMethod::grow: per_texel += 22; break;
        // The safe mask and the runs (at most one per texel, 8 bytes, with
        // their links): bounded by 1 + 3 * 8 per texel, rarely near it.
        case OpaqueMethod::cover: per_texel += 25; break;
        case OpaqueMethod::fast:
            per_texel += 28;
            // The paper's candidate quads the fast search keeps: bounded by
            // its work budget (about 64 MiB at most), fewer on small rects.
            extra = std::min<std::uint64_t>(std::uint64_t(64) << 20, 16 * texels);
            break;
        }
    return per_texel * texels + extra + (std::uint64_t(rect.w) + std::uint64_t(rect.h)) * 64 + 4096;
}

AnalyzeStatus analyze_image(ImageView image, Rect rect, const AnalyzeOptions& options, std::uint64_t max_scratch_bytes,
                            ImageAnalysis& out) {
    if (analysis_scratch_bytes(rect, options) > max_scratch_bytes) return AnalyzeStatus::over_memory_limit;
#if defined(__cpp_exceptions)
    try {
        out = analyze_image(image, rect, options);
    } catch (const std::bad_alloc&) {
        return AnalyzeStatus::out_of_memory;
    }
#else
    // Built without exceptions (the WebAssembly core): a failed allocation
    // traps there, so no status can report it.
    out = analyze_image(image, rect, options);
#endif
    return AnalyzeStatus::ok;
}

} // namespace depthcull
