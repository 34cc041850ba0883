// Overdraw heatmaps: per-pixel fragment counts as colours, panels side by
// side on one shared ramp so the same colour means the same count in every
// panel, with a legend of exact counts (counts are integers, so the legend
// is a row of swatches, not a gradient). Text uses a built-in 3x5 font so
// the picture needs no font library.
#include <algorithm>
#include <array>
#include <cstdio>

#include "depthcull/render.h"

namespace depthcull::render {

namespace {

using Rgb = std::array<std::uint8_t, 3>;

// Rows of 3 bits, top row first; bit 2 is the left column.
struct Glyph {
    char c;
    std::uint8_t rows[5];
};
constexpr Glyph kFont[] = {
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}}, {'3', {7, 1, 3, 1, 7}}, {'4', {5, 5, 7, 1, 1}},
    {'5', {7, 4, 7, 1, 7}}, {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 2, 2}}, {'8', {7, 5, 7, 5, 7}}, {'9', {7, 5, 7, 1, 7}},
    {'A', {2, 5, 7, 5, 5}}, {'B', {6, 5, 6, 5, 6}}, {'C', {3, 4, 4, 4, 3}}, {'D', {6, 5, 5, 5, 6}}, {'E', {7, 4, 6, 4, 7}},
    {'F', {7, 4, 6, 4, 4}}, {'G', {3, 4, 5, 5, 3}}, {'H', {5, 5, 7, 5, 5}}, {'I', {7, 2, 2, 2, 7}}, {'J', {1, 1, 1, 5, 2}},
    {'K', {5, 5, 6, 5, 5}}, {'L', {4, 4, 4, 4, 7}}, {'M', {5, 7, 7, 5, 5}}, {'N', {6, 5, 5, 5, 5}}, {'O', {2, 5, 5, 5, 2}},
    {'P', {6, 5, 6, 4, 4}}, {'Q', {2, 5, 5, 6, 3}}, {'R', {6, 5, 6, 5, 5}}, {'S', {3, 4, 2, 1, 6}}, {'T', {7, 2, 2, 2, 2}},
    {'U', {5, 5, 5, 5, 7}}, {'V', {5, 5, 5, 5, 2}}, {'W', {5, 5, 7, 7, 5}}, {'X', {5, 5, 2, 5, 5}}, {'Y', {5, 5, 2, 2, 2}},
    {'Z', {7, 1, 2, 4, 7}}, {'.', {0, 0, 0, 0, 2}}, {'/', {1, 1, 2, 4, 4}}, {':', {0, 2, 0, 2, 0}}, {'-', {0, 0, 7, 0, 0}},
    {'+', {0, 2, 7, 2, 0}}, {'=', {0, 7, 0, 7, 0}}, {',', {0, 0, 0, 2, 4}}, {'%', {5, 1, 2, 4, 5}}, {'(', {1, 2, 2, 2, 1}}, {')', {4, 2, 2, 2, 4}}, {'>', {4, 2, 1, 2, 4}},
};
constexpr int kScale = 2;                // font pixels are 2x2
constexpr int kCharAdvance = 4 * kScale; // 3 columns + 1 space
constexpr int kTextHeight = 5 * kScale;
constexpr int kMargin = 8;
constexpr Rgb kBackground{40, 40, 40};
constexpr Rgb kText{230, 230, 230};

// Black for 0, then cold to hot; a count of 1 is the plain "drawn once".
constexpr Rgb kStops[] = {{20, 20, 150}, {0, 110, 255}, {0, 200, 200}, {0, 190, 0},   {230, 230, 0},
                          {255, 140, 0}, {225, 0, 0},   {255, 0, 200}, {255, 255, 255}};
constexpr int kStopCount = int(sizeof kStops / sizeof kStops[0]);

Rgb ramp(std::uint32_t count, std::uint32_t max_count) {
    if (count == 0) return {0, 0, 0};
    // One stop per count while they last, so small counts read exactly;
    // beyond that, interpolate over the range.
    double t = max_count <= std::uint32_t(kStopCount) ? double(count - 1)
                                                       : double(count - 1) * (kStopCount - 1) / double(max_count - 1);
    int i = std::min(int(t), kStopCount - 1);
    double f = std::min(t - i, 1.0);
    const Rgb& a = kStops[i];
    const Rgb& b = kStops[std::min(i + 1, kStopCount - 1)];
    Rgb out;
    for (int c = 0; c < 3; ++c) out[std::size_t(c)] = std::uint8_t(a[std::size_t(c)] + f * (b[std::size_t(c)] - a[std::size_t(c)]) + 0.5);
    return out;
}

struct Canvas {
    Image image;
    Canvas(int w, int h) {
        image.width = w;
        image.height = h;
        image.rgba.resize(std::size_t(w) * std::size_t(h) * 4);
        fill(0, 0, w, h, kBackground);
    }
    void put(int x, int y, Rgb c) {
        if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
        std::uint8_t* p = &image.rgba[(std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 4];
        p[0] = c[0];
        p[1] = c[1];
        p[2] = c[2];
        p[3] = 255;
    }
    void fill(int x, int y, int w, int h, Rgb c) {
        for (int j = y; j < y + h; ++j)
            for (int i = x; i < x + w; ++i) put(i, j, c);
    }
    void text(int x, int y, const std::string& s, Rgb c) {
        for (char ch : s) {
            char up = (ch >= 'a' && ch <= 'z') ? char(ch - 'a' + 'A') : ch;
            for (const Glyph& g : kFont) {
                if (g.c != up) continue;
                for (int r = 0; r < 5; ++r)
                    for (int b = 0; b < 3; ++b)
                        if (g.rows[r] & (4 >> b)) fill(x + b * kScale, y + r * kScale, kScale, kScale, c);
            }
            x += kCharAdvance;
        }
    }
};

int text_width(const std::string& s) { return int(s.size()) * kCharAdvance; }

} // namespace

Image overdraw_heatmap(const std::vector<HeatmapPanel>& panels) {
    std::uint32_t max_count = 1;
    int panels_width = kMargin, panels_height = 0;
    for (const HeatmapPanel& p : panels) {
        if (!p.map) continue;
        for (std::uint32_t c : p.map->counts) max_count = std::max(max_count, c);
        panels_width += std::max(p.map->width, text_width(p.title)) + kMargin;
        panels_height = std::max(panels_height, p.map->height);
    }
    // Legend: one swatch per count when they fit, else every k-th count.
    const std::uint32_t step = max_count <= 40 ? 1 : (max_count + 39) / 40;
    // Wide enough for the longest label, so labels never run together.
    const int swatch = std::max(18, text_width(std::to_string(max_count / step * step)) + 2);
    const int swatches = int(max_count / step) + 1;
    const std::string legend_title = "FRAGMENTS PER PIXEL (SHADED, PASSING THE DEPTH TEST)";
    const int legend_width = std::max(swatches * (swatch + 2), text_width(legend_title)) + 2 * kMargin;
    const int width = std::max(panels_width, legend_width);
    const int title_h = kTextHeight + 6;
    const int legend_y = kMargin + title_h + panels_height + kMargin;
    const int height = legend_y + title_h + swatch + 4 + kTextHeight + kMargin;
    Canvas canvas(width, height);

    int x = kMargin;
    for (const HeatmapPanel& p : panels) {
        if (!p.map) continue;
        canvas.text(x, kMargin, p.title, kText);
        const int top = kMargin + title_h;
        for (int j = 0; j < p.map->height; ++j)
            for (int i = 0; i < p.map->width; ++i)
                canvas.put(x + i, top + j, ramp(p.map->counts[std::size_t(j) * std::size_t(p.map->width) + std::size_t(i)], max_count));
        x += std::max(p.map->width, text_width(p.title)) + kMargin;
    }

    canvas.text(kMargin, legend_y, legend_title, kText);
    for (int s = 0; s < swatches; ++s) {
        const std::uint32_t count = std::uint32_t(s) * step;
        const int sx = kMargin + s * (swatch + 2), sy = legend_y + title_h;
        canvas.fill(sx, sy, swatch, swatch, ramp(count, max_count));
        const std::string label = std::to_string(count);
        canvas.text(sx + (swatch - text_width(label) + kScale) / 2, sy + swatch + 4, label, kText);
    }
    return std::move(canvas.image);
}

} // namespace depthcull::render
