// Overdraw heatmaps, the one set of heat colours: the report's pictures
// (heat_image, legend in HTML) and `depthcull render --heatmap`'s PNG
// (overdraw_heatmap: panels side by side on the same buckets, so the same
// colour means the same count in every panel, titles and legend drawn
// with the canvas's 5x7 font).
#include <algorithm>

#include "depthcull/report.h"
#include "report/canvas.h"

namespace depthcull::report {

namespace {

// Black for nothing, then cold to hot; the last bucket holds every larger count.
constexpr Rgba kHeat[kHeatBuckets] = {{0, 0, 0, 255},     {20, 20, 150, 255}, {0, 110, 255, 255}, {0, 200, 200, 255}, {0, 190, 0, 255},
                                      {230, 230, 0, 255}, {255, 140, 0, 255}, {225, 0, 0, 255},   {255, 0, 200, 255}};

constexpr int kScale = 2;       // font pixels are 2x2
constexpr int kMargin = 8;
constexpr int kSwatch = 18;     // legend swatch side
constexpr int kSwatchGap = 6;
constexpr Rgba kBackground{40, 40, 40, 255}; // dark, so black (count 0) still reads as a panel
constexpr Rgba kText{230, 230, 230, 255};

} // namespace

Rgba heat_color(std::uint32_t count) { return kHeat[std::min<std::uint32_t>(count, kHeatBuckets - 1)]; }

std::string heat_label(int bucket) {
    return bucket >= kHeatBuckets - 1 ? std::to_string(kHeatBuckets - 1) + " or more" : std::to_string(bucket);
}

Image heat_image(int width, int height, const std::vector<std::uint32_t>& counts) {
    Image out;
    if (width <= 0 || height <= 0 || counts.size() != std::size_t(width) * std::size_t(height)) return out;
    out.width = width;
    out.height = height;
    out.rgba.resize(counts.size() * 4);
    for (std::size_t i = 0; i < counts.size(); ++i) {
        const Rgba c = heat_color(counts[i]);
        out.rgba[i * 4] = c.r, out.rgba[i * 4 + 1] = c.g, out.rgba[i * 4 + 2] = c.b, out.rgba[i * 4 + 3] = 255;
    }
    return out;
}

Image overdraw_heatmap(const std::vector<HeatmapPanel>& panels) {
    auto usable = [](const HeatmapPanel& p) {
        return p.map && p.map->width > 0 && p.map->height > 0 &&
               p.map->counts.size() == std::size_t(p.map->width) * std::size_t(p.map->height);
    };
    auto panel_width = [](const HeatmapPanel& p) { return std::max(p.map->width, text_width(p.title, kScale)); };
    int panels_width = kMargin, panels_height = 0;
    for (const HeatmapPanel& p : panels) {
        if (!usable(p)) continue;
        panels_width += panel_width(p) + kMargin;
        panels_height = std::max(panels_height, p.map->height);
    }
    // Legend: a swatch per bucket, each column as wide as its label.
    const std::string legend_title = "fragments per pixel (shaded, passing the depth test)";
    auto column_width = [](int bucket) { return std::max(kSwatch, text_width(heat_label(bucket), kScale)); };
    int swatches_width = 0;
    for (int b = 0; b < kHeatBuckets; ++b) swatches_width += column_width(b) + kSwatchGap;
    const int legend_width = std::max(swatches_width, text_width(legend_title, kScale)) + 2 * kMargin;
    const int text_h = kGlyphHeight * kScale;
    const int title_h = text_h + 6;
    const int legend_y = kMargin + title_h + panels_height + kMargin;
    const int width = std::max(panels_width, legend_width);
    const int height = legend_y + title_h + kSwatch + 4 + text_h + kMargin;
    Canvas canvas(width, height, kBackground);

    int x = kMargin;
    for (const HeatmapPanel& p : panels) {
        if (!usable(p)) continue;
        canvas.text(x, kMargin, p.title, kText, kScale);
        const int top = kMargin + title_h;
        for (int j = 0; j < p.map->height; ++j)
            for (int i = 0; i < p.map->width; ++i)
                canvas.blend(x + i, top + j, heat_color(p.map->counts[std::size_t(j) * std::size_t(p.map->width) + std::size_t(i)]));
        x += panel_width(p) + kMargin;
    }

    canvas.text(kMargin, legend_y, legend_title, kText, kScale);
    x = kMargin;
    for (int b = 0; b < kHeatBuckets; ++b) {
        const int sy = legend_y + title_h;
        canvas.fill_rect(x, sy, kSwatch, kSwatch, heat_color(std::uint32_t(b)));
        canvas.text(x, sy + kSwatch + 4, heat_label(b), kText, kScale);
        x += column_width(b) + kSwatchGap;
    }
    return canvas.take();
}

} // namespace depthcull::report
