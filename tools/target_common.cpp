#include "target_common.h"

#include <cstdio>

namespace depthcull::cli {

void add_target_option(CLI::App& cmd, std::string& target) {
    cmd.add_option("--target", target,
                   "Optimize for this renderer: a built-in profile (llvmpipe, ipad1) or a profile JSON from `depthcull calibrate` "
                   "(vertex budget, opaque polygons and hidden elements chosen for the lowest predicted frame time)")
        ->type_name("PROFILE");
}

} // namespace depthcull::cli
