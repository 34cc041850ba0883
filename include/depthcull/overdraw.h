// depthcull: the overdraw analyzers, beside reconstruction (paper 2.3)
// whose effect they measure, as meshoptimizer keeps meshopt_analyzeOverdraw
// beside meshopt_optimizeOverdraw. Geometry only: no GL, no I/O, so
// `depthcull optimize --stats`, tests and a cost model use them anywhere.
// Paper 3 measured overdraw by drawing untextured polygons with additive
// blending; counting on the CPU gives the same figure without a GPU.
#pragma once

#include <cstdint>
#include <vector>

#include "depthcull/image.h"
#include "depthcull/scene.h"

namespace depthcull {

// Per-pixel fragment counts of one frame, row-major, row 0 at the top of
// the viewport.
struct OverdrawMap {
    int width = 0, height = 0;
    std::vector<std::uint32_t> counts;
};

// Best case: shaded == ideal_overdraw's shaded (every shaded fragment is
// needed); overdraw() == 1.0 for a scene that covers every pixel once;
// rasterized == shaded when nothing is rejected by the depth test.
struct OverdrawStats {
    std::int64_t pixels = 0;     // viewport pixels
    std::int64_t shaded = 0;     // fragments that passed the depth test
    std::int64_t rasterized = 0; // fragments the triangles cover, before the depth test
    std::int64_t shaded_opaque = 0; // of shaded, those of Pass::opaque draws (the cost model prices them apart)
    // 4x4 pixel blocks (aligned to the viewport's corner) each triangle
    // covers a pixel centre of, before the depth test, summed over the
    // triangles of each pass: what llvmpipe shades (whole blocks), which
    // fragments and triangle perimeters only approximate. Counted when asked
    // (analyze_overdraw's count_blocks).
    std::int64_t blocks_opaque = 0, blocks_blend = 0;
    double overdraw() const { return pixels ? double(shaded) / double(pixels) : 0.0; }
};

// Rasterizes every triangle the way GL does (pixel centres, a tie-breaking
// fill rule so shared edges shade once, vertices snapped to 1/256 pixel,
// 24-bit depth, GL_GREATER with depth writes in Pass::opaque draws when
// meshes.depth_test) and counts fragments that pass. Matches
// GL_SAMPLES_PASSED exactly on llvmpipe (tested in tests/render). `map`,
// when given, gets the shaded count per pixel; blocks_opaque and
// blocks_blend are counted only when `count_blocks` (the cost model's
// choices rasterize many frames and price no blocks).
OverdrawStats analyze_overdraw(const SceneMeshes& meshes, OverdrawMap* map = nullptr, bool count_blocks = false);

// Where a frame's fragments above the ideal frame go (issue 25): each
// fragment the meshes shade, by the texel it samples (nearest, at the
// pixel centre, through the vertices' u, v):
struct ExcessStats {
    std::int64_t transparent = 0; // a transparent texel (inside a boundary polygon, outside the texels)
    std::int64_t hidden = 0;      // behind a fully opaque texel nearer in the same pixel, or one drawn there again
    // The rest: what the ideal frame shades too (ideal_overdraw's shaded, but
    // for centres on texel edges, which nearest sampling may give either texel).
    std::int64_t needed = 0;
    // The 4x4 blocks each triangle covers a pixel centre of (what llvmpipe
    // shades, OverdrawStats::blocks_*), by whether one of its fragments
    // there is needed: a block with none (transparent, hidden or rejected
    // fragments only) is shaded for nothing; a block with one is shaded
    // whatever the polygon's shape there.
    std::int64_t blocks_needed = 0, blocks_waste = 0;
};

// Rasterizes `meshes` as analyze_overdraw does (the depth test included:
// rejected fragments are not counted) and sorts the shaded fragments.
// Nearer: the depth plan's z where the meshes have depth values, else the
// order of drawing. A fragment hides what is behind when its texel is
// opaque and it covers as ideal_overdraw says (alpha blend with colour
// alpha 1, Blend::opaque, or the opaque pass). images[i] holds the texels
// of the meshes' image i (Draw::image).
ExcessStats excess_overdraw(const SceneMeshes& meshes, const std::vector<ImageView>& images);

// The lower limit: per pixel, walk the elements front to back and count
// those whose sampled texel (nearest, at the pixel centre) is not
// transparent, down to and including the first that is fully opaque there
// (texel alpha 255 with Blend::alpha and colour alpha 1, or Blend::opaque).
// images[i] holds Scene::images[i]'s texels. rasterized == shaded.
// `shows`, when given, gets per element 1 when it has a fragment there
// (what the ideal frame draws: the limit of depthcull/cost.h).
// blocks_opaque and blocks_blend: the 4x4 blocks (aligned to the
// viewport's corner) that the ideal frame's triangles shade, each element
// drawn as its rect's two triangles (split by the diagonal from texel
// (0, 0) to (w, h)) shading only those fragments: per element and
// triangle, the blocks it has one of them in (opaque when every one there
// hides what is behind, so an opaque pass could draw them): what the
// limit's frame (depthcull/cost.h: two triangles per element) shades on a
// renderer that shades whole blocks, as llvmpipe does (issue 25,
// docs/ideal-frame.md section 14).
OverdrawStats ideal_overdraw(const Scene& scene, const std::vector<ImageView>& images, OverdrawMap* map = nullptr,
                             std::vector<std::uint8_t>* shows = nullptr);

} // namespace depthcull
