// pipeline::atlas_with_polygons: a TexturePacker atlas loaded, every frame
// analyzed (through the cache, on threads), the polygons written by
// io::atlas_polygons_json. Frames in parallel, results by index: the text
// is the same for any thread count.
#include <atomic>

#include "depthcull/pipeline.h"
#include "io/formats.h"

namespace depthcull::pipeline {

namespace {

std::string polygons_text(const std::string& path, const AtlasPolygonOptions& options, io::AtlasPolygonStats* stats,
                          AtlasAnalysis* analysis_out) {
    AtlasAnalysis local;
    AtlasAnalysis& result = analysis_out ? *analysis_out : local;
    result.atlas = io::load_texturepacker(path); // validates every frame
    const io::Atlas& atlas = result.atlas;
    result.page = io::load_png(atlas.image_path);
    const Image& page = result.page;
    if (atlas.width > 0 && (atlas.width != page.width || atlas.height != page.height))
        throw io::Error(path + ": meta.size " + std::to_string(atlas.width) + "x" + std::to_string(atlas.height) + " differs from " +
                        atlas.image_path + " (" + std::to_string(page.width) + "x" + std::to_string(page.height) + ")");
    for (const io::AtlasFrame& frame : atlas.frames)
        if (!page.view().contains(frame.frame))
            throw io::Error(path + ": frame '" + frame.name + "': texels lie outside the page " + atlas.image_path);
    result.frames.assign(atlas.frames.size(), {});
    std::vector<std::uint8_t> hit(atlas.frames.size(), 0);
    std::atomic<std::size_t> done{0};
    parallel_for(atlas.frames.size(), options.threads, [&](std::size_t i) {
        bool from_cache = false;
        result.frames[i] = analyze_cached(page.view(), atlas.frames[i].frame, options.analyze, options.cache_dir, &from_cache);
        hit[i] = from_cache;
        if (options.progress) options.progress(++done, atlas.frames.size());
    });
    result.cache_hits = 0;
    for (std::uint8_t h : hit) result.cache_hits += h;
    return io::atlas_polygons_json(path, atlas, result.frames, stats);
}

} // namespace

std::string atlas_with_polygons(const std::string& path, const AtlasPolygonOptions& options, io::AtlasPolygonStats* stats,
                                AtlasAnalysis* analysis) {
    return io::guarded(path, [&] { return polygons_text(path, options, stats, analysis); });
}

} // namespace depthcull::pipeline
