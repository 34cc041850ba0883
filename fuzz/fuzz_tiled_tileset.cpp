// Fuzzes the external Tiled tileset reader (.tsx, gzipped or not): every
// input is a tileset whose tiles all lie inside their images, or an
// depthcull::Error. Read as tests/data/tiled/fuzz.tsx, so the images it names
// resolve to the test data there. Seeds: fuzz/corpus/tiled_tileset/.
#include <algorithm>
#include <string_view>

#include "fuzz_common.h"
#include "io/tiled_internal.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::private_cache_dir();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    namespace tiled = depthcull::io::tiled;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    std::vector<depthcull::SceneImage> images;
    tiled::ImageTable table(images);
    tiled::Tileset ts;
    try {
        ts = depthcull::io::guarded("fuzz.tsx", [&] {
            return tiled::tileset_from_bytes(bytes, DEPTHCULL_SOURCE_DIR "/tests/data/tiled/fuzz.tsx", 1, table);
        });
    } catch (const depthcull::Error&) {
        return 0;
    }
    // Every tile a gid can name (the first 4096 and the named ones) lies
    // inside its image; ids past the last name no tile.
    auto check = [&](std::uint32_t local) {
        const tiled::Tile t = ts.tile(local);
        if (t.image < 0) return;
        if (std::size_t(t.image) >= images.size()) std::abort();
        const depthcull::SceneImage& image = images[std::size_t(t.image)];
        const depthcull::Rect& r = t.rect;
        if (r.w < 1 || r.h < 1 || r.x < 0 || r.y < 0 || r.x > image.width - r.w || r.y > image.height - r.h) std::abort();
    };
    for (std::uint32_t id = 0; id < std::min<std::uint32_t>(ts.tile_count(), 4096); ++id) check(id);
    for (const auto& [id, tile] : ts.tables->named) check(id);
    if (ts.tile(ts.tile_count()).image >= 0) std::abort();
    return 0;
}
