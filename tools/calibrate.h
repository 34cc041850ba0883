// The measurement of `depthcull calibrate` (cmd_calibrate.cpp), for
// --target auto too (target_common.cpp). Only in builds with the renderer
// and the runtime (DEPTHCULL_HAVE_RENDER, DEPTHCULL_HAVE_RUNTIME).
#pragma once

#include "depthcull/cost.h"
#include "depthcull/render.h"

namespace depthcull::cli {

// Measures host's renderer term by term (quick: a few seconds, rough) and
// returns the profile of process CPU times, named "calibrated" (or
// "calibrated-software"); *wall, when given, gets the wall-clock terms.
// Throws CliError when a frame fails or a term is not finite.
CostProfile measure_profile(render::GlHost& host, bool quick, bool quiet, CostProfile* wall = nullptr);

} // namespace depthcull::cli
