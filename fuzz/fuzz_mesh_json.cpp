// Fuzzes the meshes JSON reader (docs/mesh-format.md): every input is a
// value or a depthcull::Error, never a crash; what reads back keeps the reader's
// promises (indices below their draw's vertex count, finite floats, z in
// [0, 1], draws naming existing images) and writes back to text that reads
// as the same meshes. Seeds: fuzz/corpus/mesh_json/.
#include <cmath>
#include <cstdlib>
#include <string_view>

#include "depthcull/io.h"

namespace {

void check(const depthcull::io::MeshesDocument& m) {
    for (const depthcull::Draw& d : m.meshes.draws) {
        if (d.image < 0 || std::size_t(d.image) >= m.images.size()) std::abort();
        if (d.vertices.size() % depthcull::kVertexFloats || d.indices.size() % 3) std::abort();
        for (std::uint32_t i : d.indices)
            if (i >= d.vertex_count()) std::abort();
        for (std::size_t k = 0; k < d.vertices.size(); ++k)
            if (!std::isfinite(d.vertices[k]) || (k % depthcull::kVertexFloats == 2 && (d.vertices[k] < 0 || d.vertices[k] > 1))) std::abort();
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    depthcull::io::MeshesDocument m;
    try {
        m = depthcull::io::meshes_from_json(text, "fuzz.json");
    } catch (const depthcull::Error&) {
        return 0;
    }
    check(m);
    // Written back, it reads as the same draws.
    const std::string again = depthcull::io::meshes_to_json(m, "");
    const depthcull::io::MeshesDocument back = depthcull::io::meshes_from_json(again, "again.json");
    if (back.meshes.draws.size() != m.meshes.draws.size()) std::abort();
    for (std::size_t i = 0; i < m.meshes.draws.size(); ++i)
        if (back.meshes.draws[i].vertices != m.meshes.draws[i].vertices || back.meshes.draws[i].indices != m.meshes.draws[i].indices) std::abort();
    return 0;
}
