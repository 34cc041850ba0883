// What every scene reader promises about a scene it returns (fuzz
// harnesses abort when it does not hold), and the set-up the readers that
// write files need.
#pragma once

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "depthcull/limits.h"
#include "depthcull/scene.h"

namespace fuzz {

// Elements name existing images and texels inside them, with finite
// transforms and colours in 0..1; the viewport is within the limits.
inline void check_scene(const depthcull::Scene& scene) {
    const depthcull::Viewport& v = scene.viewport;
    if (!(std::fabs(v.x) <= depthcull::limits::kMaxCoordinate && std::fabs(v.y) <= depthcull::limits::kMaxCoordinate)) std::abort();
    if (v.width < 1 || v.height < 1 || v.width > depthcull::kMaxImageSide || v.height > depthcull::kMaxImageSide) std::abort();
    for (const depthcull::SceneImage& image : scene.images)
        if (image.width < 1 || image.height < 1 || image.width > depthcull::kMaxImageSide || image.height > depthcull::kMaxImageSide)
            std::abort();
    for (const depthcull::Element& e : scene.elements) {
        if (e.image < 0 || std::size_t(e.image) >= scene.images.size()) std::abort();
        const depthcull::SceneImage& image = scene.images[std::size_t(e.image)];
        const depthcull::Rect& r = e.rect;
        if (r.w < 1 || r.h < 1 || r.x < 0 || r.y < 0 || r.x > image.width - r.w || r.y > image.height - r.h) std::abort();
        for (double t : e.transform)
            if (!std::isfinite(t)) std::abort();
        for (float c : e.color)
            if (!(c >= 0 && c <= 1)) std::abort();
    }
}

// Keyed tileset images (Tiled's trans) are written under
// $XDG_CACHE_HOME/depthcull/keyed: a fuzz run keeps them out of the user's
// cache, in a directory of its own that it returns.
// (under $TMPDIR: scripts/fuzz-smoke points it at a scratch directory it
// removes).
inline std::string private_cache_dir() {
    static const std::string dir = [] {
        std::string name = (std::filesystem::temp_directory_path() / "depthcull-fuzz.XXXXXX").string();
        if (!mkdtemp(name.data())) std::abort();
        setenv("XDG_CACHE_HOME", name.c_str(), 1);
        return name;
    }();
    return dir;
}

} // namespace fuzz
