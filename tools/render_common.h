// What `render` and `bench` share: loading and analyzing a scene the way
// `optimize` does (same options, same cache), and opening the renderer.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "cli.h"
#include "depthcull/io.h"
#include "depthcull/render.h"

namespace depthcull::cli {

struct RenderInput {
    io::PrepareOptions prepare;
    std::string cache_dir;
    bool no_cache = false;
    ReconstructOptions reconstruct;
    bool opaque = true;
    render::GlPlatform platform = render::GlPlatform::automatic;
    CLI::Option* filter_option = nullptr;
};

// --cache, --no-cache, --graph, --sort, --no-opaque, --viewport, the
// analysis options, -j, --gl.
void add_render_input_options(CLI::App& command, RenderInput& input);

io::PreparedScene prepare_for_render(const std::string& scene, const RenderInput& input);
ReconstructOptions reconstruct_options(const RenderInput& input);
std::vector<ImageView> image_views(const io::PreparedScene& prepared);

// Throws CliError("no OpenGL context: ...") when none can be made.
std::unique_ptr<render::GlRenderer> open_renderer(const RenderInput& input);

} // namespace depthcull::cli
