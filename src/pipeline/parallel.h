// Internal to the pipeline and the command line (not installed): how work
// runs on threads. Out of depthcull/pipeline.h: an engine calls the
// pipeline, never its thread pool.
#pragma once

#include <cstddef>
#include <functional>

namespace depthcull::pipeline {

// Runs fn(i) for i in [0, n) on `threads` threads (0: all cores; at most
// limits::kMaxThreads), the calling thread one of them. Threads the system
// refuses to start are not an error: those running do their share. Callers
// store results by index, so output never depends on the thread count;
// the error of the lowest failing index is rethrown, as a serial run would.
void parallel_for(std::size_t n, unsigned threads, const std::function<void(std::size_t)>& fn);

} // namespace depthcull::pipeline
