// Internal to src/pipeline: the stages optimize() strings together, for
// optimize.cpp. Not installed: callers outside the pipeline call
// optimize() (or prepare_scene / plan_target, its public stages).
#pragma once

#include <string>

#include "depthcull/pipeline.h"

namespace depthcull::pipeline {

// prepare_scene's work: load `path`, settle (settle(scene, options)) and
// write the settled filter into the scene, decode, analyze. *settled (when
// given) receives what settle decided, the profile with it.
PreparedScene prepare_settled(const std::string& path, const OptimizeOptions& options, Settled* settled);

} // namespace depthcull::pipeline
