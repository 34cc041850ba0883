// STUB until paper 2.3 lands: behaves like overpaint.
#include "depthcull/scene.h"

namespace depthcull {

ReconstructStatus reconstruct_scene(const Scene& scene, const std::vector<const ImageAnalysis*>&, const ReconstructOptions&,
                                    SceneMeshes* out) {
    *out = overpaint_meshes(scene);
    return ReconstructStatus::ok;
}

ReconstructStatus rectangle_meshes(const Scene& scene, const ReconstructOptions&, SceneMeshes* out) {
    *out = overpaint_meshes(scene);
    return ReconstructStatus::ok;
}

} // namespace depthcull
