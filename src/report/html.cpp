// The self-contained HTML report: everything embedded (images as data:
// URIs, styles inline), so one file can be mailed, attached to a CI run or
// opened offline. Pictures the browser scales keep their texels sharp
// (image-rendering: pixelated); the heatmap legend is HTML text, so it
// reads at normal zoom whatever the scene's size.
#include <algorithm>
#include <cstdio>

#include "depthcull/io.h"
#include "depthcull/report.h"
#include "report/canvas.h"
#include "report/html_text.h"

namespace depthcull::report {

namespace {

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}
std::string integer(std::int64_t v) {
    // Thousands separated by thin spaces: 1 234 567 reads at a glance.
    std::string digits = std::to_string(v < 0 ? -v : v), out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += "&#8201;";
        out += digits[i];
    }
    return v < 0 ? "-" + out : out;
}

std::string img(const Image& image, const std::string& alt, const std::string& cls, int max_side) {
    if (image.width == 0) return "<p class=\"missing\">(not drawn)</p>";
    int factor = 1;
    Image small = shrink(image.view(), max_side, &factor);
    return "<img class=\"" + cls + "\" alt=\"" + html_escape(alt) + "\" width=\"" + std::to_string(small.width) + "\" height=\"" +
           std::to_string(small.height) + "\" src=\"" + png_data_uri(small.view()) + "\">" +
           (factor > 1 ? "<br><small>shown at 1:" + std::to_string(factor) + "</small>" : "");
}

const char* kStyle = R"(
body{font:15px/1.4 system-ui,sans-serif;margin:1.5em;color:#222;background:#fafafa}
h1{font-size:1.6em}h2{font-size:1.3em;margin-top:2em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;margin:.5em 0 1em}th,td{border:1px solid #ccc;padding:.25em .6em}
th{background:#eee;text-align:left}td.n{text-align:right;font-variant-numeric:tabular-nums}
.pictures{display:flex;flex-wrap:wrap;gap:1em;align-items:flex-start}
figure{margin:0;background:#fff;border:1px solid #ddd;padding:.5em;max-width:100%}
figure img{max-width:100%;height:auto;image-rendering:pixelated;display:block}
figcaption{font-size:.95em;margin-top:.3em}
.legend{display:flex;flex-wrap:wrap;gap:.4em;align-items:center;margin:.5em 0}
.swatch{display:inline-flex;align-items:center;gap:.3em;font-size:15px}
.swatch span{display:inline-block;width:1.4em;height:1.4em;border:1px solid #888}
img.preview{max-width:360px}
.note{color:#555;font-size:.95em}
)";

} // namespace

std::string base64(std::string_view bytes) {
    static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const unsigned v = unsigned(std::uint8_t(bytes[i])) << 16 | unsigned(std::uint8_t(bytes[i + 1])) << 8 | std::uint8_t(bytes[i + 2]);
        out += kAlphabet[v >> 18];
        out += kAlphabet[(v >> 12) & 63];
        out += kAlphabet[(v >> 6) & 63];
        out += kAlphabet[v & 63];
    }
    if (i < bytes.size()) {
        unsigned v = unsigned(std::uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= unsigned(std::uint8_t(bytes[i + 1])) << 8;
        out += kAlphabet[v >> 18];
        out += kAlphabet[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? kAlphabet[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

std::string html_escape(std::string_view text) {
    std::string out;
    for (char c : text) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&#39;"; break;
        default: out += c;
        }
    }
    return out;
}

std::string png_data_uri(ImageView image) { return "data:image/png;base64," + base64(io::encode_png(image)); }

Image shrink(ImageView image, int max_side, int* factor_out) {
    const int long_side = std::max(image.width, image.height);
    const int factor = max_side > 0 && long_side > max_side ? (long_side + max_side - 1) / max_side : 1;
    if (factor_out) *factor_out = factor;
    Image out;
    out.width = (image.width + factor - 1) / factor;
    out.height = (image.height + factor - 1) / factor;
    out.rgba.resize(std::size_t(out.width) * std::size_t(out.height) * 4);
    for (int j = 0; j < out.height; ++j)
        for (int i = 0; i < out.width; ++i)
            std::copy_n(image.texel(i * factor, j * factor), 4, &out.rgba[(std::size_t(j) * std::size_t(out.width) + std::size_t(i)) * 4]);
    return out;
}

Image difference_image(ImageView a, ImageView b, std::int64_t* pixels_differ) {
    Image out;
    if (pixels_differ) *pixels_differ = 0;
    if (a.width != b.width || a.height != b.height) return out;
    out.width = a.width;
    out.height = a.height;
    out.rgba.resize(std::size_t(a.width) * std::size_t(a.height) * 4);
    for (int j = 0; j < a.height; ++j)
        for (int i = 0; i < a.width; ++i) {
            const std::uint8_t* p = a.texel(i, j);
            const std::uint8_t* q = b.texel(i, j);
            std::uint8_t* o = &out.rgba[(std::size_t(j) * std::size_t(a.width) + std::size_t(i)) * 4];
            if (p[0] != q[0] || p[1] != q[1] || p[2] != q[2] || p[3] != q[3]) {
                o[0] = 255, o[1] = 0, o[2] = 0, o[3] = 255;
                if (pixels_differ) ++*pixels_differ;
            } else {
                // Faded grey of the frame, so red stands out and the scene stays recognisable.
                const int grey = (p[0] * 30 + p[1] * 59 + p[2] * 11) / 100 * p[3] / 255;
                o[0] = o[1] = o[2] = std::uint8_t(160 + grey * 95 / 255);
                o[3] = 255;
            }
        }
    return out;
}

std::string report_html(const RunReport& run) {
    std::string h;
    h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>" + html_escape(run.title) + "</title>\n<style>" + kStyle +
         "</style>\n"
         // Says on the page whether every embedded picture decoded, for
         // readers and for the headless-browser test (dump-dom shows it).
         "<script>addEventListener('load',()=>{let ok=0,bad=0;for(const i of document.images)"
         "(i.complete&&i.naturalWidth>0)?ok++:bad++;document.body.dataset.imagesLoaded=ok;document.body.dataset.imagesBroken=bad;});"
         "</script></head><body>\n<h1>" + html_escape(run.title) + "</h1>\n";
    h += "<table id=\"options\"><tr><th>command</th><td><code>" + html_escape(run.command) + "</code></td></tr>\n";
    h += "<tr><th>renderer</th><td>" + html_escape(run.renderer) + "</td></tr>\n";
    for (const auto& [name, value] : run.options)
        h += "<tr><th>" + html_escape(name) + "</th><td>" + html_escape(value) + "</td></tr>\n";
    h += "</table>\n<p class=\"note\">Overdraw counts fragments shaded (passing the depth test) over <em>all</em> viewport pixels, so "
         "pixels nothing covers count as 0 and a scene that leaves part of the viewport empty can show less than 1. "
         "<em>covered</em> is the share of viewport pixels where some element shows a non-transparent texel. "
         "Ideal overdraw counts, per pixel, only the elements that must be shaded there.</p>\n";
    if (run.scenes.size() > 1) {
        h += "<ul>";
        for (std::size_t s = 0; s < run.scenes.size(); ++s)
            h += "<li><a href=\"#scene" + std::to_string(s) + "\">" + html_escape(run.scenes[s].path) + "</a></li>";
        h += "</ul>\n";
    }
    for (std::size_t s = 0; s < run.scenes.size(); ++s) {
        const SceneReport& r = run.scenes[s];
        const std::string id = "scene" + std::to_string(s);
        h += "<section class=\"scene\" id=\"" + id + "\">\n<h2>" + html_escape(r.path) + "</h2>\n";
        h += "<p>viewport " + std::to_string(r.width) + "&times;" + std::to_string(r.height) + " px, " + integer(std::int64_t(r.elements)) +
             " elements, " + integer(std::int64_t(r.images)) + " distinct images / tiles; covered " + fmt("%.1f", 100 * r.covered) +
             "% of the viewport" + (r.analysis.empty() ? "" : "; " + html_escape(r.analysis)) + "</p>\n";
        h += "<table class=\"table2\"><tr><th>mode</th><th>draw calls</th><th>triangles</th><th>overdraw</th><th>ideal overdraw</th>"
             "<th>overdraw / ideal</th><th>ms per frame (wall)</th><th>ms per frame (CPU)</th>" +
             (r.target.empty() ? std::string() : "<th>predicted ms (--target " + html_escape(r.target) + ")</th>") +
             (r.target.empty() ? std::string() : "<th>CPU / overpaint</th><th>CPU / limit</th>") +
             "<th>pixels differing from overpaint</th></tr>\n";
        // CPU / overpaint against the overpaint row's CPU ms (when drawn and timed).
        double overpaint_cpu = -1;
        for (const ModeRow& m : r.rows)
            if (m.mode == "overpaint") overpaint_cpu = m.cpu_ms;
        const char* names[] = {"overpaint", "meshes", "optimized"};
        const char* labels[] = {"overpaint", "meshes only", "optimized"};
        for (const ModeRow& m : r.rows) {
            std::string label = m.mode;
            for (int k = 0; k < 3; ++k)
                if (m.mode == names[k]) label = labels[k];
            h += "<tr><td>" + html_escape(label) + "</td><td class=\"n\">" + integer(m.draw_calls) + "</td><td class=\"n\">" +
                 integer(m.triangles) + "</td><td class=\"n\">" + fmt("%.3f", m.overdraw) + "</td><td class=\"n\">" +
                 fmt("%.3f", r.ideal_overdraw) + "</td><td class=\"n\">" +
                 (r.ideal_overdraw > 0 ? fmt("%.2f", m.overdraw / r.ideal_overdraw) : "-") + "</td><td class=\"n\">" +
                 (m.ms >= 0 ? fmt("%.3f", m.ms) : "-") + "</td><td class=\"n\">" + (m.cpu_ms >= 0 ? fmt("%.3f", m.cpu_ms) : "-") +
                 (r.target.empty() ? std::string() : "</td><td class=\"n\">" + (m.predicted_ms >= 0 ? fmt("%.3f", m.predicted_ms) : "-")) +
                 (r.target.empty() ? std::string()
                                   : "</td><td class=\"n\">" + (m.cpu_ms > 0 && overpaint_cpu > 0 ? fmt("%.3f", m.cpu_ms / overpaint_cpu) : "-") +
                                         "</td><td class=\"n\">" + (m.cpu_ms > 0 && r.limit_ms > 0 ? fmt("%.3f", m.cpu_ms / r.limit_ms) : "-")) +
                 "</td><td class=\"n\">" + (m.pixels_differ >= 0 ? integer(m.pixels_differ) : "-") + "</td></tr>\n";
        }
        h += "</table>\n";
        if (!r.target.empty() && r.limit_ms > 0)
            h += "<p class=\"note\">The limit: " + fmt("%.3f", r.limit_ms) + " ms, the frame time --target " + html_escape(r.target) +
                 " predicts for the ideal frame (exactly the ideal fragments, blended in one pass, one draw per texture, nothing "
                 "rejected, two triangles per element that shows). CPU / limit: how far each mode is from it.</p>\n";

        h += "<h3>Frames</h3>\n<div class=\"pictures frames\">\n";
        std::int64_t differ = 0;
        const Image diff = r.overpaint.width && r.optimized.width ? difference_image(r.overpaint.view(), r.optimized.view(), &differ) : Image{};
        h += "<figure>" + img(r.overpaint, "overpaint frame", "frame", run.max_picture_side) + "<figcaption>overpaint</figcaption></figure>\n";
        h += "<figure>" + img(r.optimized, "optimized frame", "frame", run.max_picture_side) + "<figcaption>optimized</figcaption></figure>\n";
        h += "<figure>" + img(diff, "difference", "frame diff", run.max_picture_side) + "<figcaption>difference: " +
             (diff.width ? integer(differ) + (differ == 1 ? " pixel differs" : " pixels differ") + " (red)" : std::string("-")) + "</figcaption></figure>\n</div>\n";

        if (!r.heatmaps.empty()) {
            h += "<h3>Overdraw per pixel</h3>\n<div class=\"legend\">fragments shaded per pixel: ";
            for (int b = 0; b < kHeatBuckets; ++b) {
                const Rgba c = heat_color(std::uint32_t(b));
                char colour[8];
                std::snprintf(colour, sizeof colour, "#%02x%02x%02x", c.r, c.g, c.b);
                h += "<span class=\"swatch\"><span style=\"background:" + std::string(colour) + "\"></span>" + heat_label(b) + "</span>";
            }
            h += "</div>\n<div class=\"pictures heatmaps\">\n";
            for (const HeatPanel& p : r.heatmaps)
                h += "<figure>" + img(heat_image(p.width, p.height, p.counts), p.title + " heatmap", "heat", run.max_picture_side) +
                     "<figcaption>" + html_escape(p.title) + ": overdraw " + fmt("%.3f", p.overdraw) + "</figcaption></figure>\n";
            h += "</div>\n";
        }

        h += "<h3>Images</h3>\n<table class=\"images\"><tr><th>image</th><th>vertices</th><th>excess area</th>"
             "<th>opaque polygons</th><th>opaque coverage</th><th>triangles</th><th>uses in the scene</th></tr>\n";
        for (const ImageRow& row : r.images_table) {
            h += "<tr><td>" + html_escape(row.name) + "<br>";
            if (row.preview.width) h += "<img class=\"preview\" alt=\"preview of " + html_escape(row.name) + "\" src=\"" + png_data_uri(row.preview.view()) + "\">";
            if (!row.svg.empty()) h += "<br><a download=\"preview.svg\" href=\"data:image/svg+xml;base64," + base64(row.svg) + "\">SVG</a>";
            h += "</td><td class=\"n\">" + std::to_string(row.vertices) + "</td><td class=\"n\">" + fmt("%.3f", row.excess_area_ratio) +
                 "</td><td class=\"n\">" + std::to_string(row.opaque_polygons) + "</td><td class=\"n\">" + fmt("%.1f%%", 100 * row.opaque_coverage) +
                 "</td><td class=\"n\">" + std::to_string(row.triangles) + "</td><td class=\"n\">" + integer(row.uses) + "</td></tr>\n";
        }
        h += "</table>\n";
        if (r.images_not_shown > 0)
            h += "<p class=\"note\">" + integer(std::int64_t(r.images_not_shown)) + " more images used less often are not shown.</p>\n";
        h += "</section>\n";
    }
    h += "<p class=\"note\">excess area: boundary polygon area / non-transparent texel area (1.0 is a perfect fit); opaque coverage: "
         "share of fully opaque texels inside opaque polygons (drawn front to back with the depth test).</p>\n</body></html>\n";
    return h;
}

} // namespace depthcull::report
