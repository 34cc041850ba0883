// Polygon previews: what the analysis made of one image, frame or page,
// drawn so a user can judge it before trusting it (as TexturePacker and
// SpriteAssist show their polygons): texels on a checkerboard, magnified
// by a whole factor so texels stay square, then the texel grid, the
// triangles an engine draws, the opaque polygons (filled) and the boundary
// polygons with their vertices, and the figures as a caption.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "depthcull/io.h"
#include "depthcull/report.h"
#include "report/canvas.h"
#include "report/html_text.h"
#include "depthcull/scene.h"

namespace depthcull::report {

namespace {

constexpr int kMargin = 12;
constexpr int kCaptionScale = 2;
constexpr int kCheck = 8; // checkerboard cell, screen pixels
constexpr Rgba kPaper{250, 250, 250, 255};
constexpr Rgba kInk{20, 20, 20, 255};
constexpr Rgba kCheckLight{255, 255, 255, 255}, kCheckDark{204, 204, 204, 255};
constexpr Rgba kGrid{0, 0, 0, 40};
constexpr Rgba kTriangle{30, 90, 255, 170};
constexpr Rgba kOpaqueFill{255, 200, 0, 80}, kOpaqueEdge{240, 130, 0, 255};
constexpr Rgba kBoundary{230, 0, 90, 255};

std::string hex(Rgba c) {
    char buf[8];
    std::snprintf(buf, sizeof buf, "#%02x%02x%02x", c.r, c.g, c.b);
    return buf;
}

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

// Triangles as an engine draws them: boundary polygons ear-clipped (they
// may be concave), opaque polygons (convex) the same way.
std::vector<std::array<Vec2, 3>> triangles_of(const std::vector<const ImageAnalysis*>& analyses) {
    std::vector<std::array<Vec2, 3>> out;
    for (const ImageAnalysis* a : analyses) {
        if (!a) continue;
        for (const auto* set : {&a->boundary, &a->opaque})
            for (const Polygon& p : *set) {
                const std::vector<std::uint32_t> idx = triangulate_polygon(p);
                for (std::size_t i = 0; i + 2 < idx.size(); i += 3) out.push_back({p[idx[i]], p[idx[i + 1]], p[idx[i + 2]]});
            }
    }
    return out;
}

Image crop(ImageView image, Rect rect) {
    Image out;
    out.width = rect.w;
    out.height = rect.h;
    out.rgba.resize(std::size_t(rect.w) * std::size_t(rect.h) * 4);
    for (int j = 0; j < rect.h; ++j)
        std::copy_n(image.texel(rect.x, rect.y + j), std::size_t(rect.w) * 4, &out.rgba[std::size_t(j) * std::size_t(rect.w) * 4]);
    return out;
}

} // namespace

PreviewFigures preview_figures(const std::vector<const ImageAnalysis*>& analyses) {
    PreviewFigures f;
    for (const ImageAnalysis* a : analyses) {
        if (!a) continue;
        f.boundary_polygons += int(a->boundary.size());
        f.opaque_polygons += int(a->opaque.size());
        for (const Polygon& p : a->boundary) {
            f.boundary_vertices += int(p.size());
            f.triangles += std::max(0, int(p.size()) - 2);
        }
        for (const Polygon& p : a->opaque) {
            f.opaque_vertices += int(p.size());
            f.triangles += std::max(0, int(p.size()) - 2);
        }
        f.nontransparent_texels += a->stats.nontransparent_texels;
        f.opaque_texels += a->stats.opaque_texels;
        f.opaque_covered_texels += a->stats.opaque_covered_texels;
        f.boundary_area += a->stats.boundary_area;
        f.rect_area += double(a->rect.w) * double(a->rect.h);
    }
    return f;
}

std::vector<std::string> preview_caption(const PreviewFigures& f, Rect rect, const std::string& title) {
    char buf[256];
    std::vector<std::string> lines;
    std::snprintf(buf, sizeof buf, "%dx%d at %d,%d", rect.w, rect.h, rect.x, rect.y);
    lines.push_back(title.empty() ? std::string(buf) : title + "  " + buf);
    std::snprintf(buf, sizeof buf, "boundary: %d polygon%s, %d vertices, excess area %.3f", f.boundary_polygons,
                  f.boundary_polygons == 1 ? "" : "s", f.boundary_vertices, f.excess_area_ratio());
    lines.push_back(buf);
    if (f.opaque_texels > 0)
        std::snprintf(buf, sizeof buf, "opaque: %d polygon%s, coverage %.1f%% of %lld opaque texels", f.opaque_polygons,
                      f.opaque_polygons == 1 ? "" : "s", 100.0 * f.opaque_coverage(), static_cast<long long>(f.opaque_texels));
    else
        std::snprintf(buf, sizeof buf, "opaque: no fully opaque texels");
    lines.push_back(buf);
    std::snprintf(buf, sizeof buf, "triangles: %d", f.triangles);
    lines.push_back(buf);
    return lines;
}

namespace {

// Where everything goes: the scale, the sprite's size on screen, the
// caption and the picture's size (shared by the PNG and the SVG).
struct Layout {
    Rect rect;
    int magnification = 1, shrink_by = 1;
    double scale = 1;
    int sprite_w = 0, sprite_h = 0;
    std::vector<std::string> caption;
    int swatch = 0, line_h = 0, width = 0, height = 0, caption_y = 0;
    bool grid = false;
};

Layout layout_preview(ImageView image, Rect rect, const PreviewFigures& figures, const PreviewOptions& options) {
    Layout l;
    if (rect.empty() || !image.contains(rect)) rect = image.bounds();
    l.rect = rect;
    const int long_side = std::max(rect.w, rect.h);
    // Whole factors keep texels square and the grid regular; pages larger
    // than ~4x the size are shown a texel per pixel, very large ones shrunk.
    l.magnification = std::clamp(options.size / std::max(1, long_side), 1, std::max(1, options.max_magnification));
    constexpr int kMaxSide = 4096;
    if (long_side > kMaxSide) l.shrink_by = (long_side + kMaxSide - 1) / kMaxSide;
    l.scale = l.shrink_by > 1 ? 1.0 / l.shrink_by : double(l.magnification);
    l.sprite_w = int(std::ceil(rect.w * l.scale));
    l.sprite_h = int(std::ceil(rect.h * l.scale));

    std::string title = options.title;
    title += l.shrink_by > 1 ? "  (1:" + std::to_string(l.shrink_by) + ")" : "  (x" + std::to_string(l.magnification) + ")";
    l.caption = preview_caption(figures, rect, title);
    l.swatch = kGlyphHeight * kCaptionScale; // colour key before lines 2-4
    int caption_w = 0;
    for (std::size_t i = 0; i < l.caption.size(); ++i)
        caption_w = std::max(caption_w, text_width(l.caption[i], kCaptionScale) + (i > 0 ? l.swatch + 8 : 0));
    l.line_h = kLineAdvance * kCaptionScale + 2;
    l.width = std::max(l.sprite_w, caption_w) + 2 * kMargin;
    l.caption_y = kMargin + l.sprite_h + kMargin;
    l.height = l.caption_y + int(l.caption.size()) * l.line_h + kMargin;
    l.grid = l.shrink_by == 1 && l.magnification >= options.min_grid_magnification;
    return l;
}

// The colour keys of caption lines 1-3 (boundary, opaque, triangles).
constexpr Rgba kKeys[] = {kBoundary, kOpaqueEdge, kTriangle};

Image draw_preview_png(ImageView image, const Layout& l, const std::vector<const ImageAnalysis*>& analyses,
                       const std::vector<std::array<Vec2, 3>>& triangles) {
    const Rect rect = l.rect;
    const int magnification = l.magnification, sprite_w = l.sprite_w, sprite_h = l.sprite_h, width = l.width, height = l.height;
    const int swatch = l.swatch, line_h = l.line_h, caption_y = l.caption_y;
    const double scale = l.scale;
    const bool grid = l.grid;
    const std::vector<std::string>& caption = l.caption;
    Canvas canvas(width, height, kPaper);
    auto at = [&](Vec2 p) { return Vec2{kMargin + (p.x - rect.x) * scale, kMargin + (p.y - rect.y) * scale}; };

    // Checkerboard under the texels, blended: transparency shows as the board.
    for (int j = 0; j < sprite_h; ++j)
        for (int i = 0; i < sprite_w; ++i) {
            canvas.blend(kMargin + i, kMargin + j, ((i / kCheck + j / kCheck) & 1) ? kCheckDark : kCheckLight);
            const int tx = rect.x + std::min(rect.w - 1, int(i / scale)), ty = rect.y + std::min(rect.h - 1, int(j / scale));
            const std::uint8_t* t = image.texel(tx, ty);
            canvas.blend(kMargin + i, kMargin + j, {t[0], t[1], t[2], t[3]});
        }
    if (grid) {
        for (int i = 0; i <= rect.w; ++i)
            canvas.fill_rect(kMargin + i * magnification, kMargin, 1, sprite_h, kGrid);
        for (int j = 0; j <= rect.h; ++j)
            canvas.fill_rect(kMargin, kMargin + j * magnification, sprite_w, 1, kGrid);
    }
    for (const auto& t : triangles)
        for (int k = 0; k < 3; ++k) canvas.line(at(t[std::size_t(k)]), at(t[std::size_t((k + 1) % 3)]), kTriangle, 1.0);
    for (const ImageAnalysis* a : analyses) {
        if (!a) continue;
        for (const Polygon& p : a->opaque) {
            std::vector<Vec2> s;
            for (const Vec2& v : p) s.push_back(at(v));
            canvas.fill_polygon(s, kOpaqueFill);
            canvas.outline(s, kOpaqueEdge, 2.0);
        }
    }
    const double edge = scale >= 2 ? 2.0 : 1.0;
    for (const ImageAnalysis* a : analyses) {
        if (!a) continue;
        for (const Polygon& p : a->boundary) {
            std::vector<Vec2> s;
            for (const Vec2& v : p) s.push_back(at(v));
            canvas.outline(s, kBoundary, edge);
            if (scale >= 2)
                for (const Vec2& v : s) canvas.fill_rect(int(std::lround(v.x)) - 2, int(std::lround(v.y)) - 2, 5, 5, kBoundary);
        }
    }
    for (std::size_t i = 0; i < caption.size(); ++i) {
        const int y = caption_y + int(i) * line_h;
        int x = kMargin;
        if (i > 0 && i <= 3) {
            canvas.fill_rect(x, y, swatch, swatch, kKeys[i - 1]);
            x += swatch + 8;
        }
        canvas.text(x, y, caption[i], kInk, kCaptionScale);
    }
    return canvas.take();
}

std::string draw_preview_svg(ImageView image, const Layout& l, const std::vector<const ImageAnalysis*>& analyses,
                             const std::vector<std::array<Vec2, 3>>& triangles) {
    const Rect rect = l.rect;
    const int sprite_w = l.sprite_w, sprite_h = l.sprite_h, width = l.width, height = l.height;
    const int swatch = l.swatch, line_h = l.line_h, caption_y = l.caption_y;
    const double scale = l.scale;
    const bool grid = l.grid;
    const std::vector<std::string>& caption = l.caption;
    std::string svg;
    svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) + "\" height=\"" + std::to_string(height) +
           "\" viewBox=\"0 0 " + std::to_string(width) + " " + std::to_string(height) + "\">\n";
    svg += "<defs><pattern id=\"check\" width=\"16\" height=\"16\" patternUnits=\"userSpaceOnUse\">"
           "<rect width=\"16\" height=\"16\" fill=\"#ffffff\"/><rect width=\"8\" height=\"8\" fill=\"#cccccc\"/>"
           "<rect x=\"8\" y=\"8\" width=\"8\" height=\"8\" fill=\"#cccccc\"/></pattern></defs>\n";
    svg += "<rect width=\"100%\" height=\"100%\" fill=\"" + hex(kPaper) + "\"/>\n";
    svg += "<g transform=\"translate(" + std::to_string(kMargin) + " " + std::to_string(kMargin) + ")\">\n";
    svg += "<rect width=\"" + std::to_string(sprite_w) + "\" height=\"" + std::to_string(sprite_h) + "\" fill=\"url(#check)\"/>\n";
    svg += "<image width=\"" + std::to_string(sprite_w) + "\" height=\"" + std::to_string(sprite_h) +
           "\" style=\"image-rendering:pixelated\" preserveAspectRatio=\"none\" href=\"" + png_data_uri(crop(image, rect).view()) + "\"/>\n";
    svg += "<g transform=\"scale(" + number(scale) + ") translate(" + std::to_string(-rect.x) + " " + std::to_string(-rect.y) + ")\">\n";
    if (grid) {
        svg += "<path id=\"grid\" fill=\"none\" stroke=\"#000\" stroke-opacity=\"0.16\" vector-effect=\"non-scaling-stroke\" d=\"";
        for (int i = 0; i <= rect.w; ++i) svg += "M" + std::to_string(rect.x + i) + " " + std::to_string(rect.y) + "v" + std::to_string(rect.h);
        for (int j = 0; j <= rect.h; ++j) svg += "M" + std::to_string(rect.x) + " " + std::to_string(rect.y + j) + "h" + std::to_string(rect.w);
        svg += "\"/>\n";
    }
    auto points = [](const Polygon& p) {
        std::string s;
        for (const Vec2& v : p) s += (s.empty() ? "" : " ") + number(v.x) + "," + number(v.y);
        return s;
    };
    svg += "<g id=\"triangles\" fill=\"none\" stroke=\"" + hex(kTriangle) + "\" stroke-opacity=\"0.67\" vector-effect=\"non-scaling-stroke\">\n";
    for (const auto& t : triangles) svg += "<polygon vector-effect=\"non-scaling-stroke\" points=\"" + points({t[0], t[1], t[2]}) + "\"/>\n";
    svg += "</g>\n<g id=\"opaque\" fill=\"" + hex(kOpaqueFill) + "\" fill-opacity=\"0.27\" stroke=\"" + hex(kOpaqueEdge) + "\" stroke-width=\"2\">\n";
    for (const ImageAnalysis* a : analyses)
        if (a)
            for (const Polygon& p : a->opaque) svg += "<polygon vector-effect=\"non-scaling-stroke\" points=\"" + points(p) + "\"/>\n";
    svg += "</g>\n<g id=\"boundary\" fill=\"none\" stroke=\"" + hex(kBoundary) + "\" stroke-width=\"2\">\n";
    for (const ImageAnalysis* a : analyses)
        if (a)
            for (const Polygon& p : a->boundary) svg += "<polygon vector-effect=\"non-scaling-stroke\" points=\"" + points(p) + "\"/>\n";
    svg += "</g>\n</g>\n</g>\n";
    for (std::size_t i = 0; i < caption.size(); ++i) {
        const int y = caption_y + int(i) * line_h;
        int x = kMargin;
        if (i > 0 && i <= 3) {
            svg += "<rect x=\"" + std::to_string(x) + "\" y=\"" + std::to_string(y) + "\" width=\"" + std::to_string(swatch) + "\" height=\"" +
                   std::to_string(swatch) + "\" fill=\"" + hex(kKeys[i - 1]) + "\"/>\n";
            x += swatch + 8;
        }
        svg += "<text x=\"" + std::to_string(x) + "\" y=\"" + std::to_string(y + swatch - 2) +
               "\" font-family=\"monospace\" font-size=\"15\" fill=\"" + hex(kInk) + "\">" + html_escape(caption[i]) + "</text>\n";
    }
    svg += "</svg>\n";
    return svg;
}

} // namespace

Preview make_preview(ImageView image, Rect rect, const std::vector<const ImageAnalysis*>& analyses, const PreviewOptions& options) {
    Preview out;
    out.figures = preview_figures(analyses);
    const Layout l = layout_preview(image, rect, out.figures, options);
    out.magnification = l.shrink_by > 1 ? -l.shrink_by : l.magnification;
    const auto triangles = triangles_of(analyses);
    out.png = draw_preview_png(image, l, analyses, triangles);
    out.svg = draw_preview_svg(image, l, analyses, triangles);
    return out;
}

} // namespace depthcull::report
