#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli/run_cli.h"
#include "depthcull/io.h"
#include "testing/ascii_image.h"

using namespace depthcull;
using depthcull::test::run_cli;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
    fs::path dir = fs::temp_directory_path() / ("dc_cli_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

} // namespace

TEST(AnalyzeCli, WritesTheDocumentedFields) {
    auto r = run_cli("analyze '" + test::example("art/rock.png") + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["images"].size(), 1u);
    const auto& img = j["images"][0];
    EXPECT_EQ(img["width"], 48);
    EXPECT_EQ(img["height"], 40);
    EXPECT_EQ(img["rect"], nlohmann::json({0, 0, 48, 40}));
    EXPECT_GE(img["boundary"].size(), 1u);
    EXPECT_TRUE(img["opaque"].is_array());
    for (const char* key : {"nontransparent_texels", "opaque_texels", "boundary_area", "bbox_area", "seconds",
                            "opaque_area", "opaque_covered_texels", "opaque_coverage"})
        EXPECT_TRUE(img["stats"].contains(key)) << key;
}

TEST(AnalyzeCli, SubRectangleAndPolygonsInFullImageCoordinates) {
    fs::path dir = scratch("rect");
    Image sheet = test::ascii_image({"........", "....##..", "....##..", "........"});
    io::write_png((dir / "sheet.png").string(), sheet.view());
    auto r = run_cli("analyze '" + (dir / "sheet.png").string() + ":4,0,4,4'");
    ASSERT_EQ(r.status, 0) << r.err;
    auto img = nlohmann::json::parse(r.out)["images"][0];
    EXPECT_EQ(img["rect"], nlohmann::json({4, 0, 4, 4}));
    for (const auto& poly : img["boundary"])
        for (const auto& v : poly) {
            EXPECT_GE(v[0].get<double>(), 4.0);
            EXPECT_LE(v[0].get<double>(), 8.0);
        }
    EXPECT_EQ(img["stats"]["nontransparent_texels"], 4);
}

TEST(AnalyzeCli, DirectoryInputIsSortedAndSummaryPrintsTotals) {
    auto r = run_cli("analyze '" + test::example("art") + "' -o /dev/null --summary");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("excess ratio"), std::string::npos);
    EXPECT_NE(r.out.find("images                10"), std::string::npos) << r.out;
    auto j = nlohmann::json::parse(run_cli("analyze '" + test::example("art") + "'").out);
    std::vector<std::string> paths;
    for (const auto& img : j["images"]) paths.push_back(img["path"]);
    EXPECT_TRUE(std::is_sorted(paths.begin(), paths.end()));
    EXPECT_EQ(paths.size(), 10u);
}

TEST(AnalyzeCli, OutputIsByteIdenticalWhateverTheThreadCount) {
    std::string base = "analyze --no-timing '" + test::example("art") + "'";
    auto one = run_cli(base + " -j 1");
    auto four = run_cli(base + " -j 4");
    ASSERT_EQ(one.status, 0);
    EXPECT_EQ(one.out, four.out);
    EXPECT_EQ(one.out, run_cli(base + " -j 3").out);
}

TEST(AnalyzeCli, CheckPassesOnTheExamples) {
    auto r = run_cli("analyze --check -o /dev/null '" + test::example("art") + "'");
    EXPECT_EQ(r.status, 0) << r.err;
    r = run_cli("analyze --check --filter linear -o /dev/null '" + test::example("art") + "'");
    EXPECT_EQ(r.status, 0) << r.err;
}

TEST(AnalyzeCli, CorruptFileGivesOneLineErrorAndNoOutputFile) {
    fs::path dir = scratch("corrupt");
    std::ofstream(dir / "bad.png") << "\x89PNG\r\n\x1a\n garbage";
    fs::path out = dir / "out.json";
    auto r = run_cli("analyze '" + test::example("art/rock.png") + "' '" + (dir / "bad.png").string() + "' -o '" + out.string() + "'");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("bad.png"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out));
    int left = 0;
    for (auto& e : fs::directory_iterator(dir)) (void)e, ++left;
    EXPECT_EQ(left, 1); // only bad.png: no temporary file left behind
}

TEST(AnalyzeCli, BadArgumentsAreRejected) {
    EXPECT_NE(run_cli("analyze /nonexistent.png").status, 0);
    EXPECT_NE(run_cli("analyze '" + test::example("art/rock.png") + ":40,0,20,20'").status, 0); // rect outside
    EXPECT_NE(run_cli("analyze --max-vertices 2 '" + test::example("art/rock.png") + "'").status, 0);
    EXPECT_NE(run_cli("analyze --filter cubic '" + test::example("art/rock.png") + "'").status, 0);
    // A bad name for a choice is named, with the choices by name.
    auto bad = run_cli("analyze --opaque bogus '" + test::example("art/rock.png") + "'");
    EXPECT_NE(bad.status, 0);
    EXPECT_NE(bad.err.find("--opaque: 'bogus' is not one of fast, grow, paper"), std::string::npos) << bad.err;
    fs::path dir = scratch("empty");
    auto r = run_cli("analyze '" + dir.string() + "'");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.err.find("no PNG"), std::string::npos);
}

TEST(AnalyzeCli, FullyTransparentImageGivesNoPolygon) {
    fs::path dir = scratch("transparent");
    io::write_png((dir / "clear.png").string(), test::ascii_image({"....", "...."}).view());
    auto r = run_cli("analyze '" + (dir / "clear.png").string() + "'");
    ASSERT_EQ(r.status, 0) << r.err;
    auto img = nlohmann::json::parse(r.out)["images"][0];
    EXPECT_TRUE(img["boundary"].empty());
    EXPECT_TRUE(img["opaque"].empty());
}
