// depthcull::report: the font, previews, pictures and the HTML report.
#include <cstring>

#include <gtest/gtest.h>

#include "depthcull/analyze.h"
#include "depthcull/report.h"
#include "report/canvas.h" // internal: the font is tested here
#include "report/html_text.h"

namespace report = depthcull::report;
using depthcull::Image;
using depthcull::ImageAnalysis;
using depthcull::Rect;

namespace {

Image square_sprite(int size, int inset) {
    Image img;
    img.width = img.height = size;
    img.rgba.assign(std::size_t(size) * size * 4, 0);
    for (int y = inset; y < size - inset; ++y)
        for (int x = inset; x < size - inset; ++x) {
            std::uint8_t* p = &img.rgba[(std::size_t(y) * size + x) * 4];
            p[0] = 200, p[1] = 120, p[2] = 40, p[3] = 255;
        }
    return img;
}

const std::uint8_t* pixel(const Image& img, int x, int y) { return &img.rgba[(std::size_t(y) * img.width + x) * 4]; }

} // namespace

TEST(Report, Base64MatchesRfc4648Vectors) {
    EXPECT_EQ(report::base64(""), "");
    EXPECT_EQ(report::base64("f"), "Zg==");
    EXPECT_EQ(report::base64("fo"), "Zm8=");
    EXPECT_EQ(report::base64("foo"), "Zm9v");
    EXPECT_EQ(report::base64("foobar"), "Zm9vYmFy");
}

TEST(Report, HtmlEscapeCoversMarkup) { EXPECT_EQ(report::html_escape("<a href=\"x\">&'"), "&lt;a href=&quot;x&quot;&gt;&amp;&#39;"); }

TEST(Report, TextDrawsGlyphPixelsInsideItsWidth) {
    report::Canvas c(40, 12, {255, 255, 255, 255});
    c.text(1, 1, "Hi", {0, 0, 0, 255});
    int dark = 0, outside = 0;
    const int w = report::text_width("Hi");
    EXPECT_EQ(w, 11);
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 40; ++x)
            if (pixel(c.image(), x, y)[0] == 0) {
                ++dark;
                if (x < 1 || x >= 1 + w || y < 1 || y >= 1 + report::kGlyphHeight) ++outside;
            }
    EXPECT_GT(dark, 10);
    EXPECT_EQ(outside, 0);
}

TEST(Report, PreviewMagnifiesDrawsPolygonsAndCaption) {
    Image sprite = square_sprite(32, 4);
    ImageAnalysis a = depthcull::analyze_image(sprite.view(), sprite.view().bounds(), {});
    report::PreviewOptions options;
    options.title = "square.png";
    report::Preview p = report::make_preview(sprite.view(), sprite.view().bounds(), {&a}, options);
    EXPECT_EQ(p.magnification, 8); // 256 / 32
    EXPECT_EQ(p.figures.boundary_polygons, 1);
    EXPECT_EQ(p.figures.boundary_vertices, 4);
    EXPECT_DOUBLE_EQ(p.figures.excess_area_ratio(), 1.0);
    EXPECT_GT(p.figures.opaque_coverage(), 0.5);
    EXPECT_GE(p.figures.opaque_polygons, 1);
    ASSERT_GE(p.png.width, 256);
    ASSERT_GT(p.png.height, 256 + 4 * 18); // sprite and four caption lines
    // Transparent corner texel: the checkerboard (white or light grey).
    const std::uint8_t* corner = pixel(p.png, 12 + 3, 12 + 3);
    EXPECT_TRUE(corner[0] == corner[1] && corner[1] == corner[2] && corner[0] >= 200) << int(corner[0]);
    // The boundary edge (texel x = 4 -> pixel 12 + 32) is drawn in the boundary colour.
    const std::uint8_t* edge = pixel(p.png, 12 + 32, 12 + 128);
    EXPECT_GT(edge[0], 180);
    EXPECT_LT(edge[1], 60);
    EXPECT_NE(p.svg.find("<svg"), std::string::npos);
    EXPECT_NE(p.svg.find("id=\"boundary\""), std::string::npos);
    EXPECT_NE(p.svg.find("points=\"4,4 "), std::string::npos);
    EXPECT_NE(p.svg.find("id=\"grid\""), std::string::npos);
    EXPECT_NE(p.svg.find("square.png"), std::string::npos);
    EXPECT_NE(p.svg.find("excess area 1.000"), std::string::npos);
    EXPECT_NE(p.svg.find("id=\"opaque\""), std::string::npos);
}

TEST(Report, LargePagesAreShrunkNotMagnified) {
    Image page = square_sprite(4100, 10);
    report::Preview p = report::make_preview(page.view(), page.view().bounds(), {}, {});
    EXPECT_EQ(p.magnification, -2);
    EXPECT_LT(p.png.width, 2100);
}

TEST(Report, HeatLegendLastBucketSaysOrMore) {
    EXPECT_EQ(report::heat_label(0), "0");
    EXPECT_EQ(report::heat_label(report::kHeatBuckets - 1), std::to_string(report::kHeatBuckets - 1) + " or more");
    // Counts past the last bucket share its colour.
    const report::Rgba a = report::heat_color(report::kHeatBuckets - 1), b = report::heat_color(1000);
    EXPECT_TRUE(a.r == b.r && a.g == b.g && a.b == b.b);
}

// `render --heatmap` draws on the report's buckets (one set of heat
// colours): panels side by side, each pixel heat_color of its count, the
// same picture for the same counts.
TEST(Report, OverdrawHeatmapPanelsUseTheReportsBuckets) {
    depthcull::OverdrawMap a{3, 2, {0, 1, 2, 3, 8, 40}}, b{2, 1, {5, 9}};
    const Image h = report::overdraw_heatmap({{"overpaint  od 2.0", &a}, {"optimized", &b}, {"no map", nullptr}});
    EXPECT_EQ(report::overdraw_heatmap({{"overpaint  od 2.0", &a}, {"optimized", &b}}).rgba, h.rgba);
    ASSERT_GT(h.width, 0);
    // The first panel's pixels, below its title (margin 8, title 14 + 6).
    const int x0 = 8, y0 = 8 + 14 + 6;
    for (int j = 0; j < a.height; ++j)
        for (int i = 0; i < a.width; ++i) {
            const report::Rgba c = report::heat_color(a.counts[std::size_t(j * a.width + i)]);
            const std::uint8_t* p = pixel(h, x0 + i, y0 + j);
            EXPECT_TRUE(p[0] == c.r && p[1] == c.g && p[2] == c.b && p[3] == 255) << i << "," << j;
        }
    // Counts past the last bucket take its colour: 8 and 40 look the same.
    EXPECT_EQ(0, std::memcmp(pixel(h, x0 + 1, y0 + 1), pixel(h, x0 + 2, y0 + 1), 4));
    // The second panel starts after the first's title (wider than its map).
    const int x1 = x0 + report::text_width("overpaint  od 2.0", 2) + 8;
    const report::Rgba c9 = report::heat_color(9);
    EXPECT_EQ(pixel(h, x1 + 1, y0)[0], c9.r);
    EXPECT_EQ(pixel(h, x1 + 1, y0)[2], c9.b);
    // The legend holds every bucket's colour.
    for (int bucket = 0; bucket < report::kHeatBuckets; ++bucket) {
        const report::Rgba c = report::heat_color(std::uint32_t(bucket));
        bool found = false;
        for (int y = y0 + a.height; y < h.height && !found; ++y)
            for (int x = 0; x < h.width && !found; ++x) {
                const std::uint8_t* p = pixel(h, x, y);
                found = p[0] == c.r && p[1] == c.g && p[2] == c.b;
            }
        EXPECT_TRUE(found) << "bucket " << bucket;
    }
}

TEST(Report, DifferenceImageMarksDifferingPixels) {
    Image a = square_sprite(4, 1), b = a;
    b.rgba[0] = 9;
    std::int64_t differ = 0;
    Image d = report::difference_image(a.view(), b.view(), &differ);
    EXPECT_EQ(differ, 1);
    EXPECT_EQ(pixel(d, 0, 0)[0], 255);
    EXPECT_EQ(pixel(d, 0, 0)[1], 0);
    EXPECT_EQ(pixel(d, 1, 1)[0], pixel(d, 1, 1)[1]);
}

TEST(Report, HtmlHasTablesImagesAndLegend) {
    report::RunReport run;
    run.command = "depthcull report <x>";
    run.renderer = "test";
    report::SceneReport s;
    s.path = "meadow.json";
    s.width = s.height = 4;
    s.rows = {{"overpaint", 10, 20, 1.5, 0.1, 0.1, 0}, {"optimized", 2, 30, 1.1, 0.05, 0.05, 0}};
    s.overpaint = s.optimized = square_sprite(4, 1);
    s.heatmaps.push_back({"overpaint", 2, 2, {0, 1, 2, 30}, 8.25});
    report::ImageRow row;
    row.name = "tree.png";
    row.preview = square_sprite(8, 2);
    s.images_table.push_back(row);
    run.scenes.push_back(s);
    const std::string html = report::report_html(run);
    EXPECT_NE(html.find("<table class=\"table2\">"), std::string::npos);
    EXPECT_NE(html.find("<table class=\"images\">"), std::string::npos);
    EXPECT_NE(html.find("8 or more"), std::string::npos);
    EXPECT_NE(html.find("&lt;x&gt;"), std::string::npos);
    EXPECT_NE(html.find("meshes only") == std::string::npos ? html.find("optimized") : 0, std::string::npos);
    // Images embedded, nothing fetched: 2 frames, the difference, 1 heatmap, 1 preview.
    std::size_t images = 0;
    for (std::size_t at = 0; (at = html.find("src=\"data:image/png;base64,", at)) != std::string::npos; ++at) ++images;
    EXPECT_EQ(images, 5u);
    EXPECT_EQ(html.find("http://"), std::string::npos);
    EXPECT_EQ(html.find("https://"), std::string::npos);
}

// Issue 25: with --target the table gives CPU / overpaint and CPU / limit
// per mode, and the limit itself below it.
TEST(Report, TargetRowsGiveTheLimitAndOverpaintRatios) {
    report::RunReport run;
    report::SceneReport s;
    s.path = "meadow.json";
    s.width = s.height = 4;
    s.rows = {{"overpaint", 10, 20, 1.5, 0.2, 0.2, 0, 0.21}, {"optimized", 2, 30, 1.1, 0.15, 0.15, 0, 0.14}};
    s.target = "llvmpipe";
    s.limit_ms = 0.1;
    run.scenes.push_back(s);
    const std::string html = report::report_html(run);
    EXPECT_NE(html.find("<th>CPU / overpaint</th><th>CPU / limit</th>"), std::string::npos);
    EXPECT_NE(html.find("<td class=\"n\">0.750</td><td class=\"n\">1.500</td>"), std::string::npos); // optimized
    EXPECT_NE(html.find("<td class=\"n\">1.000</td><td class=\"n\">2.000</td>"), std::string::npos); // overpaint
    EXPECT_NE(html.find("The limit: 0.100 ms"), std::string::npos);
    // Without a target neither column nor the note.
    run.scenes[0].target.clear();
    EXPECT_EQ(report::report_html(run).find("CPU / limit"), std::string::npos);
}
