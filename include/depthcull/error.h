// depthcull: the one exception of the layers that do I/O (depthcull/io.h,
// depthcull/pipeline.h, depthcull/target.h, depthcull/staged_files.h).
// Its message is one line naming the file (or the option) and what is
// wrong with it ("scene.json: element 3: unknown image id \"rok\""), so a
// caller prints what() and stops: the CLI as "depthcull: error: <what>"
// with exit status 1, the C API as DC_ERROR_IO with dc_last_error().
// The pure core (depthcull/scene.h, analyze.h, cost.h, frame.h) throws
// nothing and returns status enums instead.
#pragma once

#include <stdexcept>

namespace depthcull {

struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

} // namespace depthcull
