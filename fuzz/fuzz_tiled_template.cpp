// Fuzzes the Tiled object template reader (.tx): every input is a scene
// that keeps the reader's promises (fuzz_common.h) or a depthcull::Error.
// Templates are reached only through a map naming them by path, so each
// input is written to t.tx in a private directory holding a fixed map that
// places three objects from it (as is, resized, and with its own gid) and
// the tileset and image of tests/data/tiled. Seeds: fuzz/corpus/tiled_template/.
#include <filesystem>
#include <fstream>
#include <string>

#include "fuzz_common.h"
#include "depthcull/io.h"

namespace {

const char kMap[] = R"(<?xml version="1.0" encoding="UTF-8"?>
<map version="1.10" orientation="orthogonal" renderorder="right-down" width="4" height="4" tilewidth="4" tileheight="4" infinite="0">
 <tileset firstgid="5" source="tiles.tsx"/>
 <objectgroup id="1" name="things" draworder="index">
  <object id="1" template="t.tx"/>
  <object id="2" template="t.tx" x="4" y="8" height="8" rotation="30"/>
  <object id="3" template="t.tx" gid="5" x="0" y="16" width="4" height="4"/>
 </objectgroup>
</map>
)";

std::string dir;

} // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    namespace fs = std::filesystem;
    dir = fuzz::private_cache_dir();
    for (const char* name : {"tiles.tsx", "tiles.png"})
        fs::copy_file(fs::path(DEPTHCULL_SOURCE_DIR "/tests/data/tiled") / name, fs::path(dir) / name, fs::copy_options::overwrite_existing);
    std::ofstream(dir + "/m.tmx") << kMap;
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::ofstream(dir + "/t.tx", std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    depthcull::Scene scene;
    try {
        scene = depthcull::io::read_scene(dir + "/m.tmx");
    } catch (const depthcull::Error&) {
        return 0;
    }
    fuzz::check_scene(scene);
    return 0;
}
