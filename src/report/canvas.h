// The drawing surface of report's pictures (previews, heat images, the
// report's figures): internal to depthcull_report, out of the public
// header so it can change with the pictures it draws.
#pragma once

#include <string_view>
#include <vector>

#include "depthcull/report.h"

namespace depthcull::report {

// An RGBA picture with alpha-blended drawing (source over) and 5x7 text.
class Canvas {
public:
    Canvas(int width, int height, Rgba background);
    int width() const { return image_.width; }
    int height() const { return image_.height; }
    void blend(int x, int y, Rgba c);
    void fill_rect(int x, int y, int w, int h, Rgba c);
    // A line `thickness` pixels wide between pixel-space points.
    void line(Vec2 a, Vec2 b, Rgba c, double thickness = 1.0);
    // Closed outline, and interior filled by pixel centres (even-odd).
    void outline(const std::vector<Vec2>& points, Rgba c, double thickness = 1.0);
    void fill_polygon(const std::vector<Vec2>& points, Rgba c);
    // Text at (x, y) (top-left), each font pixel scale x scale; characters
    // outside printable ASCII draw as '?'.
    void text(int x, int y, std::string_view s, Rgba c, int scale = 1);
    const Image& image() const { return image_; }
    Image take() { return std::move(image_); }

private:
    Image image_;
};

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6, kLineAdvance = 9;
int text_width(std::string_view s, int scale = 1);

} // namespace depthcull::report
