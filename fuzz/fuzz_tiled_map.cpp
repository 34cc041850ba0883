// Fuzzes the Tiled map reader (io::read_scene over a .tmx's bytes, gzipped
// or not): every input is a scene that keeps the reader's promises
// (fuzz_common.h) or a depthcull::Error. The map is read as
// tests/data/tiled/fuzz.tmx, so the tilesets, templates and images it
// names resolve to the test data there. Seeds: fuzz/corpus/tiled_map/.
#include <string_view>

#include "fuzz_common.h"
#include "io/formats.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::private_cache_dir();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    depthcull::Scene scene;
    try {
        scene = depthcull::io::scene_from_bytes(bytes, DEPTHCULL_SOURCE_DIR "/tests/data/tiled/fuzz.tmx");
    } catch (const depthcull::Error&) {
        return 0;
    }
    fuzz::check_scene(scene);
    return 0;
}
