// Fuzzes the binary meshes reader (docs/mesh-format.md): every input is a
// value or a depthcull::Error, never a crash, and no count makes it allocate more
// than the input holds; what reads back keeps the reader's promises and
// writes back byte for byte (the form has one encoding per value),
// animations included.
// Seeds: fuzz/corpus/mesh_binary/.
#include <cmath>
#include <cstdlib>
#include <string_view>

#include "depthcull/io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    depthcull::io::MeshesDocument m;
    try {
        m = depthcull::io::meshes_from_binary(bytes, "fuzz.bin");
    } catch (const depthcull::Error&) {
        return 0;
    }
    for (const depthcull::Draw& d : m.meshes.draws) {
        if (d.image < 0 || std::size_t(d.image) >= m.images.size() || d.indices.size() % 3) std::abort();
        for (std::uint32_t i : d.indices)
            if (i >= d.vertex_count()) std::abort();
        for (float v : d.vertices)
            if (!std::isfinite(v)) std::abort();
    }
    // The reader accepts one encoding per value (zero padding, known flags),
    // so what it accepted is written back byte for byte.
    for (const depthcull::io::AnimatedRun& r : m.animated)
        if (r.draw >= m.meshes.draws.size() || r.animation >= m.animations.size() || r.vertex_count == 0 ||
            std::uint64_t(r.first_vertex) + r.vertex_count > m.meshes.draws[r.draw].vertex_count())
            std::abort();
    if (depthcull::io::meshes_to_binary(m, "") != bytes) std::abort();
    return 0;
}
