// depthcull report / bench --report: one self-contained HTML page, opened
// in headless Chromium (Debian package chromium; skipped without it).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "cli/run_cli.h"
#include "depthcull/io.h"

using depthcull::test::example;
using depthcull::test::run_cli;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return depthcull::test::scratch_dir("report_" + name); }

const auto& shq = depthcull::test::shell_quote;

const auto& slurp = depthcull::test::read_bytes;

std::string chromium() {
    for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
        std::string cmd = std::string("command -v ") + name + " >/dev/null 2>&1";
        if (std::system(cmd.c_str()) == 0) return name;
    }
    return {};
}

std::size_t count(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = 0; (at = text.find(what, at)) != std::string::npos; at += what.size()) ++n;
    return n;
}

} // namespace

TEST(ReportCli, WritesOneSelfContainedPage) {
    fs::path dir = scratch("page");
    auto r = run_cli("report " + shq(example("meadow.json")) + " -o " + shq(dir / "r.html") + " --frames 1 --warmup 0 --no-cache");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("written to"), std::string::npos) << r.err;
    const std::string html = slurp(dir / "r.html");
    EXPECT_EQ(count(html, "<table class=\"table2\">"), 1u);
    EXPECT_EQ(count(html, "<table class=\"images\">"), 1u);
    EXPECT_NE(html.find(">meshes only<"), std::string::npos);
    EXPECT_NE(html.find("8 or more"), std::string::npos);
    EXPECT_NE(html.find("all</em> viewport pixels"), std::string::npos);
    EXPECT_NE(html.find("llvmpipe") == std::string::npos ? html.find("renderer") : 0, std::string::npos);
    // Frames (2), difference, 3 heatmaps, and a preview per distinct image (10).
    EXPECT_EQ(count(html, "src=\"data:image/png;base64,"), 16u);
    EXPECT_EQ(count(html, "src=\"http"), 0u);
    // -q: nothing on stderr.
    auto q = run_cli("report " + shq(example("meadow.json")) + " -o " + shq(dir / "q.html") + " --frames 0 --warmup 0 -q");
    ASSERT_EQ(q.status, 0) << q.err;
    EXPECT_EQ(q.err, "");
}

// A new user's first command: the game's sprite folder, no scene yet. The
// folder is laid out as a contact sheet (io::read_sprite_folder) and
// reported like any scene: Table 2, frames, heatmaps, a row per sprite.
TEST(ReportCli, ASpriteFolderIsReportedAsAContactSheet) {
    fs::path dir = scratch("folder");
    auto r = run_cli("report " + shq(example("art")) + " -o " + shq(dir / "r.html") + " --frames 0 --warmup 0 --no-cache -q");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string html = slurp(dir / "r.html");
    EXPECT_EQ(count(html, "<table class=\"table2\">"), 1u);
    EXPECT_EQ(count(html, "<table class=\"images\">"), 1u);
    EXPECT_NE(html.find("tree.png"), std::string::npos);
    // One PNG alone works too; an empty folder is a one-line error.
    auto one = run_cli("render " + shq(example("art/tree.png")) + " --mode optimized -o " + shq(dir / "tree-frame.png") + " --no-cache");
    EXPECT_EQ(one.status, 0) << one.err;
    fs::create_directories(dir / "empty");
    auto empty = run_cli("optimize " + shq(dir / "empty") + " -o " + shq(dir / "m.json") + " --no-cache");
    EXPECT_EQ(empty.status, 1);
    EXPECT_NE(empty.err.find("no PNG images"), std::string::npos) << empty.err;
}

TEST(ReportCli, BenchWritesTheSameReport) {
    fs::path dir = scratch("bench");
    auto r = run_cli("bench " + shq(example("meadow.json")) + " --frames 1 --warmup 0 --report " + shq(dir / "b.html"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("covered"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("all viewport pixels"), std::string::npos) << r.out;
    const std::string html = slurp(dir / "b.html");
    EXPECT_EQ(count(html, "<table class=\"table2\">"), 1u);
    EXPECT_EQ(count(html, "<figure>"), 6u);
}

TEST(ReportCli, RendersInHeadlessChromium) {
    const std::string browser = chromium();
    if (browser.empty()) GTEST_SKIP() << "chromium not installed (apt-get install chromium)";
    fs::path dir = scratch("chromium");
    auto r = run_cli("report " + shq(example("meadow.json")) + " -o " + shq(dir / "r.html") + " --frames 1 --warmup 0 -q");
    ASSERT_EQ(r.status, 0) << r.err;
    const std::string flags = " --headless --no-sandbox --disable-gpu --hide-scrollbars --user-data-dir=" + shq(dir / "profile") + " ";
    const std::string url = "file://" + (dir / "r.html").string();
    // The DOM after load: every embedded picture decoded (the page's own
    // check), the tables there.
    const std::string dump = (dir / "dom.html").string();
    ASSERT_EQ(std::system(("timeout 60 " + browser + flags + "--dump-dom '" + url + "' > '" + dump + "' 2>/dev/null").c_str()), 0);
    const std::string dom = slurp(dump);
    std::smatch m;
    ASSERT_TRUE(std::regex_search(dom, m, std::regex("data-images-loaded=\"(\\d+)\""))) << dom.substr(0, 400);
    EXPECT_EQ(std::stoi(m[1]), 16);
    EXPECT_NE(dom.find("data-images-broken=\"0\""), std::string::npos);
    EXPECT_NE(dom.find("<table class=\"table2\">"), std::string::npos);
    EXPECT_NE(dom.find("<table class=\"images\">"), std::string::npos);

    // A screenshot: the frames (meadow is mostly grass green) and the
    // heatmaps show as pictures, not as broken-image boxes.
    const fs::path shot = dir / "shot.png";
    ASSERT_EQ(std::system(("timeout 60 " + browser + flags + "--window-size=1400,2400 --screenshot='" + shot.string() + "' '" + url +
                           "' >/dev/null 2>&1")
                              .c_str()),
              0);
    const depthcull::Image png = depthcull::io::read_png(shot.string());
    ASSERT_EQ(png.width, 1400);
    ASSERT_EQ(png.height, 2400);
    std::int64_t green = 0, heat_blue = 0;
    for (std::size_t i = 0; i < png.rgba.size(); i += 4) {
        const int r8 = png.rgba[i], g8 = png.rgba[i + 1], b8 = png.rgba[i + 2];
        green += g8 > r8 + 40 && g8 > b8 + 40;
        heat_blue += r8 == 20 && g8 == 20 && b8 == 150; // overdraw 1 in the heatmaps
    }
    const double pixels = double(png.width) * png.height;
    EXPECT_GT(green / pixels, 0.10) << "frames not drawn";
    EXPECT_GT(heat_blue / pixels, 0.01) << "heatmaps not drawn";
}
