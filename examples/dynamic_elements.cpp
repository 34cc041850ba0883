// Dynamic elements on top of an optimized static scene (beyond the paper,
// its section 4 caveat 2): the static scene is reconstructed once with a
// reserved depth range; each frame, moving sprites are added in front of it
// without touching the static meshes.
//
//   dynamic_elements SCENE.json [OUT_DIR]
//
// Prints the draw calls per frame and, with OUT_DIR, writes each frame's
// meshes (docs/mesh-format.md) as frame_N.json.
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "depthcull/scene.h"

using namespace depthcull;

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SCENE.json [OUT_DIR]\n", argv[0]);
        return 2;
    }
    try {
        // Static part: optimized once (pipeline::optimize: load, analyze,
        // reconstruct), with room for 256 moving sprites.
        pipeline::OptimizeOptions options;
        options.reconstruct.reserved_dynamic_levels = 256;
        const pipeline::OptimizeResult optimized = pipeline::optimize(argv[1], options);
        const pipeline::PreparedScene& p = optimized.prepared;
        if (p.scene.elements.empty()) throw depthcull::Error(std::string(argv[1]) + ": scene has no elements");
        if (optimized.status != ReconstructStatus::ok) throw depthcull::Error(std::string(argv[1]) + ": reconstruction failed");
        const SceneMeshes& static_meshes = optimized.meshes;
        std::printf("static: %" PRId64 " elements, %" PRId64 " draw calls, %" PRId64 " depth levels\n",
                    static_meshes.stats.elements, static_meshes.stats.draw_calls, static_meshes.stats.depth_levels);

        // Moving sprites reuse the scene's images and their analyses: the
        // last few distinct elements of the scene, orbiting the viewport's
        // centre.
        const std::size_t sprites = std::min<std::size_t>(16, p.scene.elements.size());
        const double cx = p.scene.viewport.x + p.scene.viewport.width / 2.0;
        const double cy = p.scene.viewport.y + p.scene.viewport.height / 2.0;
        for (int frame = 0; frame < 3; ++frame) {
            std::vector<Element> moving;
            std::vector<const ImageAnalysis*> analyses;
            for (std::size_t k = 0; k < sprites; ++k) {
                std::size_t source = p.scene.elements.size() - 1 - k;
                Element e = p.scene.elements[source];
                double angle = 0.4 * frame + 6.2831853 * double(k) / double(sprites);
                e.transform = {1, 0, 0, 1, cx + 150 * std::cos(angle), cy + 100 * std::sin(angle)};
                moving.push_back(e);
                analyses.push_back(p.analysis.of(source));
            }
            SceneMeshes meshes;
            if (add_dynamic_elements(static_meshes, p.scene, moving, analyses, &meshes) != ReconstructStatus::ok)
                throw depthcull::Error("frame " + std::to_string(frame) + ": too many dynamic elements for the reserved depth range");
            // `meshes` holds this frame's own draws; the frame is them around the static ones.
            meshes = compose_frame(static_meshes, meshes);
            std::printf("frame %d: %zu moving sprites, %" PRId64 " draw calls, %" PRId64 " triangles, %" PRId64 " depth levels\n",
                        frame, moving.size(), meshes.stats.draw_calls, meshes.stats.triangles, meshes.stats.depth_levels);
            if (argc > 2) {
                std::filesystem::create_directories(argv[2]);
                io::write_meshes_json((std::filesystem::path(argv[2]) / ("frame_" + std::to_string(frame) + ".json")).string(),
                                      io::meshes_document(p.scene, std::move(meshes)));
            }
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "dynamic_elements: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
