// Issue 25: the cost model's prices for clipping hidden parts
// (ReconstructOptions::clip_hidden, src/scene/clip_hidden.cpp).
#include "depthcull/cost.h"

namespace depthcull {

ClipHiddenOptions clip_hidden_options(const CostProfile& p) {
    ClipHiddenOptions o;
    o.enabled = p.fragment_rejected_ns > 0;
    // A cut fragment is one the depth test would reject (or, for an opaque
    // tile drawn before its occluder, overwrite: dearer), so the rejected
    // price is the saving's lower bound.
    o.fragment_cost = p.fragment_rejected_ns;
    o.triangle_cost = p.triangle_us * 1000;
    o.perimeter_cost = p.triangle_perimeter_ns_per_pixel;
    return o;
}

} // namespace depthcull
