// Fuzzes the TexturePacker atlas reader (hash and array JSON forms): every
// input is an atlas whose frames are found by name and, once
// check_atlas_pages has passed them against a page of the stated size (the
// reader checks frames against the decoded page, not meta.size), lie inside
// it, and place where they belong, or a depthcull::Error.
// Seeds: fuzz/corpus/texturepacker/.
#include <array>
#include <cmath>
#include <cstdlib>
#include <string_view>

#include "io/formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    depthcull::io::Atlas atlas;
    try {
        atlas = depthcull::io::texturepacker_from_text(text, "atlas/fuzz.json");
        std::vector<std::array<int, 2>> sizes;
        for (const depthcull::io::AtlasPage& page : atlas.pages)
            sizes.push_back(page.width > 0 ? std::array<int, 2>{page.width, page.height}
                                           : std::array<int, 2>{depthcull::kMaxImageSide, depthcull::kMaxImageSide});
        depthcull::io::check_atlas_pages(atlas, sizes);
    } catch (const depthcull::Error&) {
        return 0;
    }
    for (const depthcull::io::AtlasFrame& f : atlas.frames) {
        if (atlas.find(f.name) != &f) std::abort();
        const depthcull::Rect& r = f.frame;
        if (r.x < 0 || r.y < 0 || r.w < 1 || r.h < 1) std::abort();
        if (atlas.width > 0 && (r.x > atlas.width - r.w || r.y > atlas.height - r.h)) std::abort();
        const depthcull::io::FramePlacement p = depthcull::io::place_frame(f, {1, 0, 0, 1, 0, 0});
        if (p.rect.w != r.w || p.rect.h != r.h) std::abort();
        for (double t : p.transform)
            if (!std::isfinite(t)) std::abort();
    }
    return 0;
}
