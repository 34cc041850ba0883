// Only in builds with the renderer (DEPTHCULL_BUILD_RENDER).
#ifdef DEPTHCULL_HAVE_RENDER
#include "render_common.h"

#include <map>

namespace depthcull::cli {

void add_render_input_options(CLI::App& cmd, RenderInput& in) {
    cmd.add_option("--cache", in.cache_dir, "Analysis cache directory (default: $XDG_CACHE_HOME/depthcull or ~/.cache/depthcull/analysis)");
    cmd.add_flag("--no-cache", in.no_cache, "Analyze every image, read and write no cache");
    add_reconstruct_options(cmd, in.reconstruct);
    cmd.add_flag("!--no-opaque", in.opaque, "Optimized without the opaque pass: boundary polygons only");
    add_viewport_option(cmd, in.prepare.load);
    add_analysis_options(cmd, in.prepare.analyze);
    in.filter_option = cmd.get_option("--filter");
    cmd.add_option("-j,--threads", in.prepare.threads, "Worker threads for the analysis (0: all cores)")->capture_default_str();
    cmd.add_option("--gl", in.platform,
                   "EGL platform: auto (a GPU device if any, else Mesa surfaceless), surfaceless, device")
        ->transform(choice<render::GlPlatform>({{"auto", render::GlPlatform::automatic},
                                                {"surfaceless", render::GlPlatform::surfaceless},
                                                {"device", render::GlPlatform::device}}))
        ->default_str("auto");
}

io::PreparedScene prepare_for_render(const std::string& scene, const RenderInput& in) {
    io::PrepareOptions prepare = in.prepare;
    prepare.analyze.opaque.filter = prepare.analyze.boundary.filter;
    prepare.filter_from_scene = !in.filter_option || in.filter_option->count() == 0;
    if (!in.no_cache) prepare.cache_dir = in.cache_dir.empty() ? io::default_cache_dir() : in.cache_dir;
    io::PreparedScene prepared = io::prepare_scene(scene, prepare);
    // --filter given: draw with the filtering the polygons were made for.
    if (!prepare.filter_from_scene) prepared.scene.filter = prepare.analyze.boundary.filter;
    return prepared;
}

ReconstructOptions reconstruct_options(const RenderInput& in) {
    ReconstructOptions options = in.reconstruct;
    options.opaque_polygons = in.opaque;
    return options;
}

std::vector<ImageView> image_views(const io::PreparedScene& prepared) {
    std::vector<ImageView> views;
    views.reserve(prepared.images.size());
    for (const Image& image : prepared.images) views.push_back(image.view());
    return views;
}

std::unique_ptr<render::GlRenderer> open_renderer(const RenderInput& in) {
    std::string error;
    auto renderer = render::GlRenderer::create({in.platform}, &error);
    if (!renderer) throw CliError(error + " (headless rendering needs Mesa's EGL: apt-get install libegl-mesa0 libgl1-mesa-dri)");
    return renderer;
}

} // namespace depthcull::cli
#endif
