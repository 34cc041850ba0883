// depthcull::report: pictures and pages that show what depthcull did.
//
// Polygon previews (per image, atlas frame or page: the texels on a
// checkerboard, magnified, with boundary polygons, opaque polygons,
// triangles, the texel grid and the figures as a caption) as PNG pixels and
// SVG text, and the self-contained HTML report of `depthcull report` /
// `bench --report` (images embedded as data: URIs). Text in PNGs uses a
// built-in 5x7 bitmap font, so no font library is needed. Nothing here
// touches the file system or GL: callers pass what they measured and write
// what they get back. The drawing surface they are made on is internal
// (src/report/canvas.h).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "depthcull/analyze.h"
#include "depthcull/image.h"
#include "depthcull/overdraw.h"

namespace depthcull::report {

struct Rgba {
    std::uint8_t r = 0, g = 0, b = 0, a = 255;
};

// ---- Polygon previews

struct PreviewOptions {
    int size = 256;             // the sprite is magnified (whole factors) to about this many pixels on its long side
    int max_magnification = 32;
    int min_grid_magnification = 6; // texel grid drawn from this magnification up
    std::string title;          // first caption line (e.g. the file name)
};

// The figures a preview shows, summed over the analyses drawn.
struct PreviewFigures {
    int boundary_polygons = 0, boundary_vertices = 0;
    int opaque_polygons = 0, opaque_vertices = 0;
    int triangles = 0;                  // boundary and opaque polygons triangulated
    std::int64_t nontransparent_texels = 0, opaque_texels = 0, opaque_covered_texels = 0;
    double boundary_area = 0, rect_area = 0;
    double excess_area_ratio() const { return nontransparent_texels ? boundary_area / double(nontransparent_texels) : 0.0; }
    double opaque_coverage() const { return opaque_texels ? double(opaque_covered_texels) / double(opaque_texels) : 0.0; }
};
PreviewFigures preview_figures(const std::vector<const ImageAnalysis*>& analyses);

struct Preview {
    Image png;            // the picture with its caption
    std::string svg;      // the same as vector graphics; the texels embedded as a PNG data: URI
    int magnification = 1; // screen pixels per texel (negative: texels per screen pixel, for large pages)
    PreviewFigures figures;
};

// `rect` of `image` (an image, a frame, or a whole page) with the polygons
// of `analyses` (texel coordinates of the full image, as ImageAnalysis
// stores them) drawn over it.
Preview make_preview(ImageView image, Rect rect, const std::vector<const ImageAnalysis*>& analyses, const PreviewOptions& options);

// The caption lines of a preview.
std::vector<std::string> preview_caption(const PreviewFigures& figures, Rect rect, const std::string& title);

// ---- Pictures for the report

// A copy no larger than max_side per side (whole-factor nearest
// subsampling), so reports of big scenes stay loadable.
Image shrink(ImageView image, int max_side, int* factor = nullptr);

// Where two frames differ: differing pixels red, the rest the first frame
// faded to grey. Sizes must match (else an empty image).
Image difference_image(ImageView a, ImageView b, std::int64_t* pixels_differ = nullptr);

// Overdraw counts (row-major) as colours in kHeatBuckets buckets:
// 0, 1, ..., kHeatBuckets - 2, and "kHeatBuckets - 1 or more".
inline constexpr int kHeatBuckets = 9;
Rgba heat_color(std::uint32_t count);
Image heat_image(int width, int height, const std::vector<std::uint32_t>& counts);
// The label of bucket i: "0", "1", ..., "8 or more".
std::string heat_label(int bucket);

struct HeatmapPanel {
    std::string title;  // drawn above the panel
    const OverdrawMap* map = nullptr;
};
// `depthcull render --heatmap`: panels side by side, each pixel coloured by
// heat_color (the same buckets as the report), each title above its panel,
// and a legend of the buckets below. Panels without a map (or whose counts
// do not match its size) are left out.
Image overdraw_heatmap(const std::vector<HeatmapPanel>& panels);

// ---- HTML

// data:image/png;base64,... of an image (encoded by io::encode_png).
std::string png_data_uri(ImageView image);

// One Table 2 row of a scene.
struct ModeRow {
    std::string mode; // overpaint, meshes, optimized
    std::int64_t draw_calls = 0, triangles = 0;
    double overdraw = 0;        // fragments shaded / viewport pixels
    double ms = 0, cpu_ms = 0;  // median per frame; negative: not measured
    std::int64_t pixels_differ = -1; // against overpaint; negative: not compared
    double predicted_ms = -1;   // the cost model's (--target); negative: none
};

struct ImageRow {
    std::string name;           // image id or path, and the rect
    Rect rect;
    int vertices = 0;
    double excess_area_ratio = 0, opaque_coverage = 0;
    int opaque_polygons = 0, triangles = 0;
    std::int64_t uses = 0;      // elements of the scene drawing it
    Image preview;              // with its caption
    std::string svg;            // optional: linked as a data: URI
};

struct HeatPanel {
    std::string title;
    int width = 0, height = 0;
    std::vector<std::uint32_t> counts;
    double overdraw = 0;
};

struct SceneReport {
    std::string path;
    int width = 0, height = 0;  // viewport
    std::size_t elements = 0, images = 0;
    double ideal_overdraw = 0;
    double covered = 0;         // share of viewport pixels showing a non-transparent texel
    std::vector<ModeRow> rows;
    Image overpaint, optimized; // frames (empty when not drawn)
    std::vector<HeatPanel> heatmaps;
    std::vector<ImageRow> images_table;
    std::size_t images_not_shown = 0;
    std::string analysis; // e.g. "12 images analyzed, 30 from the cache"
    std::string target;   // --target profile name, when predicted_ms is given
    // --target: the limit, the ideal frame's predicted ms (depthcull/cost.h
    // limit_ms); with target, CPU / limit and CPU / overpaint are shown.
    double limit_ms = -1; // negative: none
};

struct RunReport {
    std::string title = "depthcull report";
    std::string command;  // the command line
    std::string renderer; // GL renderer description
    std::vector<std::pair<std::string, std::string>> options; // name, value
    std::vector<SceneReport> scenes;
    int max_picture_side = 2048; // frames and heatmaps larger than this are subsampled
};

// One self-contained HTML page (no external resources).
std::string report_html(const RunReport& run);

} // namespace depthcull::report
