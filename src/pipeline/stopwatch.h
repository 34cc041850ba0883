// Wall time since construction. Timing lives at the edges (pipeline::optimize,
// the CLI): the library's result values hold no clock readings, so they are
// the same on every run.
#pragma once

#include <chrono>

namespace depthcull::pipeline {

class Stopwatch {
public:
    double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

private:
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

} // namespace depthcull::pipeline
