// Random test images for property tests (rapidcheck generators and a plain
// seeded generator for loops).
#pragma once

#include <cstdint>

#include <rapidcheck.h>

#include "depthcull/image.h"

namespace depthcull::test {

struct ShapeParams {
    int width = 32, height = 32;
    int blobs = 3;           // filled discs / boxes / triangles
    int holes = 1;           // transparent discs cut out afterwards
    bool translucent_rim = true; // alpha ramps at shape edges
    bool noise = false;      // isolated random texels
};

// Deterministic: the same seed and params give the same image.
Image random_shape(std::uint64_t seed, const ShapeParams& params);

// rapidcheck generator over sizes 1..max_side and all shape parameters.
rc::Gen<Image> gen_shape(int max_side = 48);

} // namespace depthcull::test
