// Test images drawn as ASCII art, one character per texel:
//   '.' or ' '  transparent (alpha 0)
//   '#'         opaque (alpha 255)
//   '+'         translucent (alpha 128)
//   '1'..'9'    alpha = digit * 25 (all translucent)
#pragma once

#include <string>
#include <vector>

#include "depthcull/image.h"

namespace depthcull::test {

Image ascii_image(const std::vector<std::string>& rows);
// Renders an image's alpha classes back to ASCII ('.', '+', '#').
std::vector<std::string> ascii_rows(ImageView image);

} // namespace depthcull::test
