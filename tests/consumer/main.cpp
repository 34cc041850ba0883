// A downstream project: finds the installed depthcull with find_package and
// optimizes a scene through the public API only.
#include <cstdio>

#include <depthcull/analyze.h>
#include <depthcull/io.h>
#include <depthcull/pipeline.h>
#include <depthcull/render.h>
#include <depthcull/scene.h>

int main(int argc, char** argv) {
    if (argc < 2) return 2;
    depthcull::pipeline::PreparedScene s = depthcull::pipeline::prepare_scene(argv[1], {});
    depthcull::SceneMeshes meshes;
    if (depthcull::reconstruct_scene(s.scene, s.analysis, {}, &meshes) != depthcull::ReconstructStatus::ok) return 1;
    std::printf("%zu elements -> %zu draws\n", s.scene.elements.size(), meshes.draws.size());
    return meshes.draws.empty();
}
