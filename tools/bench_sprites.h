// depthcull bench --sprites N / --bunnymark N (issue 23): moving sprites
// measured frame by frame against what engines do today; the measurement
// is render::measure_sprites (src/render/measure_sprites.cpp).
#pragma once

#include <string>
#include <vector>

#include "render_common.h"

namespace depthcull::cli {

struct SpriteBenchArgs {
    std::vector<std::string> scenes;
    int sprites = 0;   // --sprites N: in the game layer of each scene
    int bunnymark = 0; // --bunnymark N: alone (the scene gives its pictures)
    int frames = 60;
    std::uint32_t seed = 23;
    bool json = false;
    std::string output;
    bool quiet = false;
    int lp_threads = -1;
    const RenderInput* input = nullptr;
};

void run_sprite_bench(const SpriteBenchArgs& args);

} // namespace depthcull::cli
