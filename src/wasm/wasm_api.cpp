// depthcull's WebAssembly entry points (issue 24): the pure core built with
// clang --target=wasm32-wasi, called from web/src/*.js.
//
// Why not the C API of include/depthcull/depthcull.h: it catches exceptions
// at its boundary and pulls in depthcull_io (files, PNG, JSON), and this
// toolchain has neither exceptions (__cxa_throw does not link) nor a file
// system worth the name. The core needs neither, so this layer is thin:
//   - every call returns a status (DCW_OK = 0) and leaves a one-line message
//     for dcw_last_error, worded as the CLI words the same error;
//   - results go into one flat buffer of doubles (dcw_result, dcw_result_size)
//     that JavaScript reads straight out of linear memory;
//   - numbers arrive as doubles and are checked here, so a fractional,
//     infinite or NaN option from JavaScript is an error, not a silent
//     truncation to int, and the checks live in one place.
// Running out of memory traps (operator new aborts without exceptions); the
// JavaScript side turns the trap into an error and makes a fresh instance.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "depthcull/analyze.h"
#include "depthcull/image.h"

#define DCW_EXPORT(name) __attribute__((export_name(#name)))

namespace {

using namespace depthcull;

enum Status : int { DCW_OK = 0, DCW_ERROR_INVALID_ARGUMENT = 1 };

std::string g_error;
std::vector<double> g_result;

int fail(std::string message) {
    g_error = std::move(message);
    return DCW_ERROR_INVALID_ARGUMENT;
}

// %.17g would print 0.75 as 0.75 but 0.1 as 0.10000000000000001; the
// shortest form that reads back the same is what a user typed.
std::string number_text(double v) {
    if (std::isnan(v)) return "NaN"; // as JavaScript prints them
    if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
    char buf[32];
    if (v == std::floor(v) && std::fabs(v) < 1e15) {
        std::snprintf(buf, sizeof buf, "%.0f", v); // 20000, not 2e+04
        return buf;
    }
    for (int precision = 1; precision <= 17; ++precision) {
        std::snprintf(buf, sizeof buf, "%.*g", precision, v);
        if (std::strtod(buf, nullptr) == v) break;
    }
    return buf;
}

// The CLI's (CLI11's) wording: "--max-vertices: Value 2 not in range 4 to
// 1000", with the JavaScript option's name.
bool int_option(const char* name, double v, int lo, int hi, int* out, std::string* error) {
    if (!std::isfinite(v) || v != std::floor(v)) {
        *error = std::string(name) + ": Value " + number_text(v) + " is not an integer";
        return false;
    }
    if (v < lo || v > hi) {
        *error = std::string(name) + ": Value " + number_text(v) + " not in range " + std::to_string(lo) + " to " + std::to_string(hi);
        return false;
    }
    *out = int(v);
    return true;
}

void append_polygons(const std::vector<Polygon>& polygons) {
    g_result.push_back(double(polygons.size()));
    for (const Polygon& p : polygons) {
        g_result.push_back(double(p.size()));
        for (const Vec2& v : p) {
            g_result.push_back(v.x);
            g_result.push_back(v.y);
        }
    }
}

} // namespace

extern "C" {

// Linear memory for the caller's pixels (JavaScript cannot call malloc).
DCW_EXPORT(dcw_alloc) void* dcw_alloc(std::uint32_t bytes) { return std::malloc(bytes ? bytes : 1); }
DCW_EXPORT(dcw_free) void dcw_free(void* p) { std::free(p); }

DCW_EXPORT(dcw_last_error) const char* dcw_last_error() { return g_error.c_str(); }
DCW_EXPORT(dcw_result) const double* dcw_result() { return g_result.data(); }
DCW_EXPORT(dcw_result_size) std::uint32_t dcw_result_size() { return std::uint32_t(g_result.size()); }

// Per-image analysis (paper 2.1, 2.2) of `rect` in the RGBA8 image at
// `rgba` (width * height * 4 bytes, rows packed, non-premultiplied), with
// the options of `depthcull analyze`. `name` (UTF-8, may be null) starts
// each error message, as the CLI starts it with the file's path.
// `filter`: 0 nearest, 1 linear. `opaque_method`: 0 paper, 1 fast, 2 grow.
// On DCW_OK the result buffer holds, as doubles:
//   boundary polygon count, then per polygon its vertex count and x, y pairs;
//   the same for the opaque polygons;
//   the stats: nontransparent_texels, opaque_texels, boundary_area,
//   bbox_area, boundary_vertices, opaque_area, opaque_covered_texels,
//   opaque_coverage.
DCW_EXPORT(dcw_analyze)
int dcw_analyze(const std::uint8_t* rgba, double width, double height, double rx, double ry, double rw, double rh,
                double max_vertices, double split, double filter, double opaque_method, double max_opaque,
                double min_coverage, double min_opaque_area, const char* name) {
    g_result.clear();
    const std::string who = name && *name ? std::string(name) : std::string("image");
    std::string error;
    int w = 0, h = 0;
    if (!int_option("width", width, 1, kMaxImageSide, &w, &error) || !int_option("height", height, 1, kMaxImageSide, &h, &error))
        return fail(who + ": " + error);
    if (std::int64_t(w) * h > kMaxImageTexels)
        return fail(who + ": " + std::to_string(w) + "x" + std::to_string(h) + " image exceeds " +
                    std::to_string(kMaxImageTexels) + " texels");
    if (!rgba) return fail(who + ": no pixels");
    Rect rect;
    if (!int_option("rect.x", rx, -kMaxImageSide, kMaxImageSide, &rect.x, &error) ||
        !int_option("rect.y", ry, -kMaxImageSide, kMaxImageSide, &rect.y, &error) ||
        !int_option("rect.width", rw, 0, kMaxImageSide, &rect.w, &error) ||
        !int_option("rect.height", rh, 0, kMaxImageSide, &rect.h, &error))
        return fail(who + ": " + error);
    const ImageView image{rgba, w, h, std::ptrdiff_t(w) * 4};
    if (rect.empty() || !image.contains(rect))
        return fail(who + ": rectangle " + std::to_string(rect.x) + "," + std::to_string(rect.y) + "," + std::to_string(rect.w) +
                    "," + std::to_string(rect.h) + " is outside the " + std::to_string(w) + "x" + std::to_string(h) + " image");

    AnalyzeOptions options;
    int split_flag = 1, filter_value = 0, method = 1;
    if (!int_option("maxVertices", max_vertices, 4, 1000, &options.boundary.max_vertices, &error) ||
        !int_option("split", split, 0, 1, &split_flag, &error) || !int_option("filter", filter, 0, 1, &filter_value, &error) ||
        !int_option("opaque", opaque_method, 0, 2, &method, &error) ||
        !int_option("maxOpaque", max_opaque, 0, 64, &options.opaque.max_polygons, &error) ||
        !int_option("minOpaqueArea", min_opaque_area, 1, 1 << 30, &options.opaque.min_area, &error))
        return fail(error);
    if (!std::isfinite(min_coverage) || min_coverage < 0 || min_coverage > 1)
        return fail("minCoverage: Value " + number_text(min_coverage) + " not in range 0 to 1");
    options.opaque.min_coverage = min_coverage;
    options.boundary.split_parts = split_flag != 0;
    options.filter = filter_value ? Filter::linear : Filter::nearest;
    options.opaque.method = method == 0 ? OpaqueMethod::paper : method == 2 ? OpaqueMethod::grow : OpaqueMethod::fast;

    const ImageAnalysis a = analyze_image(image, rect, options);
    append_polygons(a.boundary);
    append_polygons(a.opaque);
    const ImageStats& s = a.stats;
    for (double v : {double(s.nontransparent_texels), double(s.opaque_texels), s.boundary_area, s.bbox_area,
                     double(s.boundary_vertices), s.opaque_area, double(s.opaque_covered_texels), s.opaque_coverage})
        g_result.push_back(v);
    return DCW_OK;
}

} // extern "C"
