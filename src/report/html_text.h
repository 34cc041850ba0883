// Text helpers of the report's HTML and SVG: internal to depthcull_report
// (callers get whole pages and pictures, not their pieces).
#pragma once

#include <string>
#include <string_view>

namespace depthcull::report {

std::string base64(std::string_view bytes);
// &, <, >, " and ' as entities: safe in text and in quoted attributes.
std::string html_escape(std::string_view text);

} // namespace depthcull::report
