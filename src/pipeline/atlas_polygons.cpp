// pipeline::atlas_with_polygons: an atlas loaded (any io::read_atlas
// form), every frame analyzed on its page (through the cache, on threads),
// the polygons written by io::atlas_polygons_json or, for a plist,
// io::atlas_polygons_plist. Frames in parallel, results by index: the text
// is the same for any thread count.
#include <array>
#include <atomic>

#include "depthcull/pipeline.h"
#include "pipeline/parallel.h"

namespace depthcull::pipeline {

namespace {

std::string polygons_text(const std::string& path, const AtlasPolygonOptions& options, io::AtlasPolygonStats* stats,
                          AtlasAnalysis* analysis_out) {
    AtlasAnalysis local;
    AtlasAnalysis& result = analysis_out ? *analysis_out : local;
    result.atlas = io::read_atlas(path); // every frame's fields; the pages below
    const io::Atlas& atlas = result.atlas;
    const bool plist = options.plist || atlas.form == io::AtlasForm::cocos2d_plist;
    // Refused before any frame is analyzed.
    if (plist && atlas.pages.size() > 1)
        throw depthcull::Error(path + ": a cocos2d-x plist holds one page; this multipack has " + std::to_string(atlas.pages.size()) +
                        " (write JSON, or one plist per page)");
    // Every page is decoded and held: their total is checked on the
    // headers first (three pages naming one 16384^2 PNG are 3 GiB).
    std::uint64_t decoded_bytes = 0;
    for (const io::AtlasPage& p : atlas.pages) {
        int w = 0, h = 0;
        io::image_size(p.image_path, &w, &h);
        decoded_bytes += std::uint64_t(w) * std::uint64_t(h) * 4;
        if (decoded_bytes > limits::kMaxDecodedBytes)
            throw depthcull::Error(path + ": page " + p.image_path + " (" + std::to_string(w) + "x" + std::to_string(h) + ") brings the decoded pages to " +
                            std::to_string((decoded_bytes + (1 << 20) - 1) >> 20) + " MiB, over the limit of " +
                            std::to_string(limits::kMaxDecodedBytes >> 20) + " MiB (kMaxDecodedBytes)");
    }
    result.pages.clear();
    std::vector<std::array<int, 2>> sizes;
    std::vector<std::string> decoded; // what the decodes assumed
    for (const io::AtlasPage& p : atlas.pages) {
        result.pages.push_back(io::read_image(p.image_path, &decoded));
        sizes.push_back({result.pages.back().width, result.pages.back().height});
    }
    result.page = result.pages.front();
    // Frames are texels of the decoded pages; a stated size that differs
    // is a warning, as is what the reader and the decodes assumed.
    io::check_atlas_pages(result.atlas, sizes);
    std::vector<std::string> warnings = atlas.warnings;
    warnings.insert(warnings.end(), decoded.begin(), decoded.end());
    io::LoadOptions report;
    report.warning = options.warning;
    report.strict = options.strict;
    io::report_warnings(warnings, report);
    result.frames.assign(atlas.frames.size(), {});
    std::vector<std::uint8_t> hit(atlas.frames.size(), 0);
    std::atomic<std::size_t> done{0};
    parallel_for(atlas.frames.size(), options.threads, [&](std::size_t i) {
        bool from_cache = false;
        result.frames[i] = analyze_cached(result.pages[std::size_t(atlas.frames[i].page)].view(), atlas.frames[i].frame, options.analyze,
                                          options.cache_dir, &from_cache, atlas.pages[std::size_t(atlas.frames[i].page)].image_path + ": frame '" +
                                          atlas.frames[i].name + "'", options.memory);
        hit[i] = from_cache;
        if (options.progress) options.progress(++done, atlas.frames.size());
    });
    result.cache_hits = 0;
    for (std::uint8_t h : hit) result.cache_hits += h;
    if (plist) return io::atlas_polygons_plist(path, atlas, result.page.view(), result.frames, options.analyze.filter, stats);
    return io::atlas_polygons_json(path, atlas, result.frames, stats);
}

} // namespace

std::string atlas_with_polygons(const std::string& path, const AtlasPolygonOptions& options, io::AtlasPolygonStats* stats,
                                AtlasAnalysis* analysis) {
    return io::guarded(path, [&] { return polygons_text(path, options, stats, analysis); });
}

} // namespace depthcull::pipeline
