// Canvas: alpha-blended drawing into an RGBA image, and a 5x7 bitmap font
// of our own for captions, so pictures need no font library.
#include <algorithm>
#include <cmath>

#include "depthcull/report.h"
#include "report/canvas.h"

namespace depthcull::report {

namespace {

// Printable ASCII from ' ' (32) to '~' (126); 7 rows per glyph, top row
// first, bit 4 the leftmost of 5 columns.
constexpr std::uint8_t kFont[95][7] = {
    {0, 0, 0, 0, 0, 0, 0},         {4, 4, 4, 4, 4, 0, 4},          {10, 10, 0, 0, 0, 0, 0},       {10, 10, 31, 10, 31, 10, 10},
    {4, 15, 20, 14, 5, 30, 4},     {24, 25, 2, 4, 8, 19, 3},       {12, 18, 20, 8, 21, 18, 13},   {4, 4, 0, 0, 0, 0, 0},
    {2, 4, 8, 8, 8, 4, 2},         {8, 4, 2, 2, 2, 4, 8},          {0, 4, 21, 14, 21, 4, 0},      {0, 4, 4, 31, 4, 4, 0},
    {0, 0, 0, 0, 12, 4, 8},        {0, 0, 0, 31, 0, 0, 0},         {0, 0, 0, 0, 0, 12, 12},       {0, 1, 2, 4, 8, 16, 0},
    {14, 17, 19, 21, 25, 17, 14},  {4, 12, 4, 4, 4, 4, 14},        {14, 17, 1, 2, 4, 8, 31},      {31, 2, 4, 2, 1, 17, 14},
    {2, 6, 10, 18, 31, 2, 2},      {31, 16, 30, 1, 1, 17, 14},     {6, 8, 16, 30, 17, 17, 14},    {31, 1, 2, 4, 8, 8, 8},
    {14, 17, 17, 14, 17, 17, 14},  {14, 17, 17, 15, 1, 2, 12},     {0, 12, 12, 0, 12, 12, 0},     {0, 12, 12, 0, 12, 4, 8},
    {2, 4, 8, 16, 8, 4, 2},        {0, 0, 31, 0, 31, 0, 0},        {8, 4, 2, 1, 2, 4, 8},         {14, 17, 1, 2, 4, 0, 4},
    {14, 17, 1, 13, 21, 21, 14},   {14, 17, 17, 17, 31, 17, 17},   {30, 17, 17, 30, 17, 17, 30},  {14, 17, 16, 16, 16, 17, 14},
    {28, 18, 17, 17, 17, 18, 28},  {31, 16, 16, 30, 16, 16, 31},   {31, 16, 16, 30, 16, 16, 16},  {14, 17, 16, 23, 17, 17, 15},
    {17, 17, 17, 31, 17, 17, 17},  {14, 4, 4, 4, 4, 4, 14},        {7, 2, 2, 2, 2, 18, 12},       {17, 18, 20, 24, 20, 18, 17},
    {16, 16, 16, 16, 16, 16, 31},  {17, 27, 21, 21, 17, 17, 17},   {17, 17, 25, 21, 19, 17, 17},  {14, 17, 17, 17, 17, 17, 14},
    {30, 17, 17, 30, 16, 16, 16},  {14, 17, 17, 17, 21, 18, 13},   {30, 17, 17, 30, 20, 18, 17},  {15, 16, 16, 14, 1, 1, 30},
    {31, 4, 4, 4, 4, 4, 4},        {17, 17, 17, 17, 17, 17, 14},   {17, 17, 17, 17, 17, 10, 4},   {17, 17, 17, 21, 21, 21, 10},
    {17, 17, 10, 4, 10, 17, 17},   {17, 17, 17, 10, 4, 4, 4},      {31, 1, 2, 4, 8, 16, 31},      {14, 8, 8, 8, 8, 8, 14},
    {0, 16, 8, 4, 2, 1, 0},        {14, 2, 2, 2, 2, 2, 14},        {4, 10, 17, 0, 0, 0, 0},       {0, 0, 0, 0, 0, 0, 31},
    {8, 4, 2, 0, 0, 0, 0},         {0, 0, 14, 1, 15, 17, 15},      {16, 16, 22, 25, 17, 17, 30},  {0, 0, 14, 16, 16, 17, 14},
    {1, 1, 13, 19, 17, 17, 15},    {0, 0, 14, 17, 31, 16, 14},     {6, 9, 8, 28, 8, 8, 8},        {0, 15, 17, 17, 15, 1, 14},
    {16, 16, 22, 25, 17, 17, 17},  {4, 0, 12, 4, 4, 4, 14},        {2, 0, 6, 2, 2, 18, 12},       {16, 16, 18, 20, 24, 20, 18},
    {12, 4, 4, 4, 4, 4, 14},       {0, 0, 26, 21, 21, 17, 17},     {0, 0, 22, 25, 17, 17, 17},    {0, 0, 14, 17, 17, 17, 14},
    {0, 0, 30, 17, 30, 16, 16},    {0, 0, 13, 19, 15, 1, 1},       {0, 0, 22, 25, 16, 16, 16},    {0, 0, 14, 16, 14, 1, 30},
    {8, 8, 28, 8, 8, 9, 6},        {0, 0, 17, 17, 17, 19, 13},     {0, 0, 17, 17, 17, 10, 4},     {0, 0, 17, 17, 21, 21, 10},
    {0, 0, 17, 10, 4, 10, 17},     {0, 0, 17, 17, 15, 1, 14},      {0, 0, 31, 2, 4, 8, 31},       {2, 4, 4, 8, 4, 4, 2},
    {4, 4, 4, 4, 4, 4, 4},         {8, 4, 4, 2, 4, 4, 8},          {0, 0, 8, 21, 2, 0, 0},
};

} // namespace

Canvas::Canvas(int width, int height, Rgba background) {
    image_.width = std::max(0, width);
    image_.height = std::max(0, height);
    image_.rgba.resize(std::size_t(image_.width) * std::size_t(image_.height) * 4);
    for (std::size_t i = 0; i < image_.rgba.size(); i += 4) {
        image_.rgba[i] = background.r;
        image_.rgba[i + 1] = background.g;
        image_.rgba[i + 2] = background.b;
        image_.rgba[i + 3] = background.a;
    }
}

void Canvas::blend(int x, int y, Rgba c) {
    if (x < 0 || y < 0 || x >= image_.width || y >= image_.height || c.a == 0) return;
    std::uint8_t* p = &image_.rgba[(std::size_t(y) * std::size_t(image_.width) + std::size_t(x)) * 4];
    // Source over, with the destination's alpha kept at least the source's.
    const int a = c.a;
    p[0] = std::uint8_t((c.r * a + p[0] * (255 - a) + 127) / 255);
    p[1] = std::uint8_t((c.g * a + p[1] * (255 - a) + 127) / 255);
    p[2] = std::uint8_t((c.b * a + p[2] * (255 - a) + 127) / 255);
    p[3] = std::uint8_t(a + (p[3] * (255 - a) + 127) / 255);
}

void Canvas::fill_rect(int x, int y, int w, int h, Rgba c) {
    const int x0 = std::max(0, x), y0 = std::max(0, y);
    const int x1 = std::min(image_.width, x + w), y1 = std::min(image_.height, y + h);
    for (int j = y0; j < y1; ++j)
        for (int i = x0; i < x1; ++i) blend(i, j, c);
}

void Canvas::line(Vec2 a, Vec2 b, Rgba c, double thickness) {
    // Coverage from the distance of each pixel centre to the segment: an
    // antialiased line of the given width, with no special cases.
    const double r = thickness / 2;
    const int x0 = std::max(0, int(std::floor(std::min(a.x, b.x) - r - 1)));
    const int y0 = std::max(0, int(std::floor(std::min(a.y, b.y) - r - 1)));
    const int x1 = std::min(image_.width - 1, int(std::ceil(std::max(a.x, b.x) + r + 1)));
    const int y1 = std::min(image_.height - 1, int(std::ceil(std::max(a.y, b.y) + r + 1)));
    const Vec2 d = b - a;
    const double len2 = d.x * d.x + d.y * d.y;
    for (int j = y0; j <= y1; ++j)
        for (int i = x0; i <= x1; ++i) {
            const Vec2 p{i + 0.5, j + 0.5};
            double t = len2 > 0 ? ((p.x - a.x) * d.x + (p.y - a.y) * d.y) / len2 : 0;
            t = std::clamp(t, 0.0, 1.0);
            const Vec2 q = a + t * d;
            const double dist = std::hypot(p.x - q.x, p.y - q.y);
            const double cover = std::clamp(r + 0.5 - dist, 0.0, 1.0);
            if (cover > 0) blend(i, j, {c.r, c.g, c.b, std::uint8_t(c.a * cover + 0.5)});
        }
}

void Canvas::outline(const std::vector<Vec2>& points, Rgba c, double thickness) {
    for (std::size_t i = 0; i < points.size(); ++i) line(points[i], points[(i + 1) % points.size()], c, thickness);
}

void Canvas::fill_polygon(const std::vector<Vec2>& points, Rgba c) {
    if (points.size() < 3) return;
    double y_min = points[0].y, y_max = points[0].y;
    for (const Vec2& p : points) y_min = std::min(y_min, p.y), y_max = std::max(y_max, p.y);
    const int j0 = std::max(0, int(std::floor(y_min))), j1 = std::min(image_.height - 1, int(std::ceil(y_max)));
    std::vector<double> xs;
    for (int j = j0; j <= j1; ++j) {
        const double y = j + 0.5;
        xs.clear();
        for (std::size_t i = 0; i < points.size(); ++i) {
            const Vec2 a = points[i], b = points[(i + 1) % points.size()];
            // Half-open in y, so a vertex on the scan line counts once.
            if ((a.y <= y && y < b.y) || (b.y <= y && y < a.y)) xs.push_back(a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y));
        }
        std::sort(xs.begin(), xs.end());
        for (std::size_t k = 0; k + 1 < xs.size(); k += 2) {
            const int i0 = std::max(0, int(std::ceil(xs[k] - 0.5))), i1 = std::min(image_.width - 1, int(std::ceil(xs[k + 1] - 0.5)) - 1);
            for (int i = i0; i <= i1; ++i) blend(i, j, c);
        }
    }
}

void Canvas::text(int x, int y, std::string_view s, Rgba c, int scale) {
    for (char ch : s) {
        const unsigned u = static_cast<unsigned char>(ch);
        const std::uint8_t* rows = kFont[(u >= 32 && u <= 126 ? u : unsigned('?')) - 32];
        for (int r = 0; r < kGlyphHeight; ++r)
            for (int b = 0; b < kGlyphWidth; ++b)
                if (rows[r] & (16 >> b)) fill_rect(x + b * scale, y + r * scale, scale, scale, c);
        x += kGlyphAdvance * scale;
    }
}

int text_width(std::string_view s, int scale) { return s.empty() ? 0 : (int(s.size()) * kGlyphAdvance - 1) * scale; }

} // namespace depthcull::report
