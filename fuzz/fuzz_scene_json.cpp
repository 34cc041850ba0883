// Fuzzes our scene JSON reader (io::read_scene over bytes): every input is
// a scene that keeps the reader's promises (fuzz_common.h) or a depthcull::Error.
// The scene is read as examples/fuzz.json, so the paths it names resolve
// like the bundled example's (art/*.png, atlas/sheet.json). Seeds:
// fuzz/corpus/scene_json/.
#include <string_view>

#include "fuzz_common.h"
#include "io/formats.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    depthcull::Scene scene;
    try {
        scene = depthcull::io::scene_from_bytes(text, DEPTHCULL_SOURCE_DIR "/examples/fuzz.json");
    } catch (const depthcull::Error&) {
        return 0;
    }
    fuzz::check_scene(scene);
    return 0;
}
