// Animated elements (Element::animation): one analysis for all frames, so
// the optimized meshes of frame 0 draw every frame correctly once an engine
// moves the UVs to it. The analysis runs on an image combining the frames'
// alpha (0 where every frame is transparent, 255 where every frame is
// opaque, 128 elsewhere): its boundary polygons then hold the union of the
// frames' non-transparent texels and its opaque polygons only texels
// opaque in all of them. Polygons are moved onto frame 0's rect.
#include "depthcull/pipeline.h"

namespace depthcull::pipeline {

ImageAnalysis analyze_animation(const std::vector<ImageView>& images, const Animation& animation, const AnalyzeOptions& options,
                                const std::string& cache_dir, bool* hit, const std::string& name, MemoryBudget* budget) {
    const Image combined = animation_alpha(images, animation);
    ImageAnalysis a = analyze_cached(combined.view(), {0, 0, combined.width, combined.height}, options, cache_dir, hit, name, budget);
    place_animation_analysis(a, images, animation);
    return a;
}

} // namespace depthcull::pipeline
