// Issue 16: previews, progress on terminals only, one analysis cache for
// every command, no silent clamps or dumps, overdraw said plainly.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/run_cli.h"
#include "depthcull/io.h"

using depthcull::test::example;
using depthcull::test::run_cli;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return depthcull::test::scratch_dir("i16_" + name); }

const auto& shq = depthcull::test::shell_quote;

const auto& slurp = depthcull::test::read_bytes;

bool have_script() { return std::system("command -v script >/dev/null 2>&1") == 0; }

// Runs the CLI with stdout and stderr on a pseudo-terminal (util-linux
// `script`), returning everything the terminal showed.
std::string on_terminal(const std::string& args) {
    const fs::path log = fs::temp_directory_path() / ("dc_i16_tty_" + std::to_string(::getpid()));
    const std::string inner = std::string("'") + DEPTHCULL_CLI_PATH + "' " + args;
    std::string quoted;
    for (char c : inner) quoted += c == '"' ? std::string("\\\"") : std::string(1, c);
    const std::string cmd = "script -qec \"" + quoted + "\" /dev/null > '" + log.string() + "' 2>&1 < /dev/null";
    (void)std::system(cmd.c_str());
    std::string out = slurp(log);
    fs::remove(log);
    return out;
}

} // namespace

TEST(PreviewCli, AnalyzeWritesPngAndSvgPerImage) {
    fs::path dir = scratch("preview");
    auto r = run_cli("analyze " + shq(example("art")) + " --no-cache -o " + shq(dir / "a.json") + " --preview " + shq(dir / "p"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("10 previews"), std::string::npos) << r.err;
    int pngs = 0, svgs = 0;
    for (auto& e : fs::directory_iterator(dir / "p")) (e.path().extension() == ".png" ? pngs : svgs) += 1;
    EXPECT_EQ(pngs, 10);
    EXPECT_EQ(svgs, 10);
    const depthcull::Image png = depthcull::io::read_png((dir / "p" / "tree.png").string());
    EXPECT_GE(png.width, 256); // magnified
    const std::string svg = slurp(dir / "p" / "tree.svg");
    EXPECT_NE(svg.find("id=\"boundary\""), std::string::npos);
    EXPECT_NE(svg.find("<polygon"), std::string::npos);
    EXPECT_NE(svg.find("excess area"), std::string::npos);
    EXPECT_NE(svg.find("data:image/png;base64,"), std::string::npos);
}

TEST(PreviewCli, AtlasWritesPageAndFramePreviews) {
    fs::path dir = scratch("atlas_preview");
    auto r = run_cli("atlas " + shq(example("atlas/sheet.json")) + " --no-cache -o " + shq(dir / "s.json") + " --preview " + shq(dir / "p"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "p" / "sheet.png"));
    EXPECT_TRUE(fs::exists(dir / "p" / "sheet.svg"));
    EXPECT_TRUE(fs::exists(dir / "p" / "frames" / "0000_circle.png"));
    EXPECT_TRUE(fs::exists(dir / "p" / "frames" / "0003_two-dots.svg"));
}

TEST(CacheCli, AnalyzeFillsTheCacheOptimizeReads) {
    fs::path dir = scratch("cache");
    auto a = run_cli("analyze " + shq(example("art")) + " --cache " + shq(dir / "c") + " --summary");
    ASSERT_EQ(a.status, 0) << a.err;
    // (Images with the same alphas share an entry, so even a first run may hit.)
    EXPECT_NE(a.out.find("from the cache"), std::string::npos) << a.out;
    auto again = run_cli("analyze " + shq(example("art")) + " --cache " + shq(dir / "c") + " --summary");
    EXPECT_NE(again.out.find("from the cache        10 of 10"), std::string::npos) << again.out;
    auto o = run_cli("optimize " + shq(example("meadow.json")) + " --cache " + shq(dir / "c") + " --stats -o " + shq(dir / "m.json"));
    ASSERT_EQ(o.status, 0) << o.err;
    EXPECT_NE(o.out.find("images analyzed 0, from cache 10"), std::string::npos) << o.out;
    auto none = run_cli("analyze " + shq(example("art")) + " --no-cache --cache " + shq(dir / "c") + " --summary");
    EXPECT_NE(none.out.find("from the cache        0 of 10"), std::string::npos) << none.out;
}

TEST(CacheCli, AtlasUsesTheCacheAndAnyThreadCount) {
    fs::path dir = scratch("atlas_cache");
    const std::string atlas = "atlas " + shq(example("atlas/sheet.json")) + " --cache " + shq(dir / "c");
    auto one = run_cli(atlas + " -j 1 -o " + shq(dir / "1.json"));
    ASSERT_EQ(one.status, 0) << one.err;
    EXPECT_NE(one.err.find("0 of 4 frames from the analysis cache"), std::string::npos) << one.err;
    auto four = run_cli(atlas + " -j 4 -o " + shq(dir / "4.json"));
    EXPECT_NE(four.err.find("4 of 4 frames from the analysis cache"), std::string::npos) << four.err;
    auto fresh = run_cli("atlas " + shq(example("atlas/sheet.json")) + " --no-cache -j 3 -o " + shq(dir / "3.json"));
    ASSERT_EQ(fresh.status, 0) << fresh.err;
    EXPECT_EQ(slurp(dir / "1.json"), slurp(dir / "4.json"));
    EXPECT_EQ(slurp(dir / "1.json"), slurp(dir / "3.json"));
}

TEST(ProgressCli, OnlyOnATerminalAndNotWithQuiet) {
    // Not a terminal: nothing on stderr.
    auto plain = run_cli("analyze " + shq(example("art")) + " --no-cache -o /dev/null");
    ASSERT_EQ(plain.status, 0);
    EXPECT_EQ(plain.err, "");
    if (!have_script()) GTEST_SKIP() << "no `script` (util-linux) to make a pseudo-terminal";
    const std::string tty = on_terminal("analyze " + shq(example("art")) + " --no-cache -o /dev/null");
    EXPECT_NE(tty.find("analyze: "), std::string::npos) << tty;
    EXPECT_NE(tty.find("/10 images"), std::string::npos) << tty;
    EXPECT_NE(tty.find('\r'), std::string::npos) << "one line, rewritten";
    const std::string quiet = on_terminal("analyze " + shq(example("art")) + " --no-cache -o /dev/null -q");
    EXPECT_EQ(quiet.find("images"), std::string::npos) << quiet;
    const std::string bench = on_terminal("bench " + shq(example("meadow.json")) + " --frames 0 --warmup 0 --no-cache -o /dev/null");
    EXPECT_NE(bench.find("/1 scenes"), std::string::npos) << bench;
    const std::string atlas = on_terminal("atlas " + shq(example("atlas/sheet.json")) + " --no-cache -o /dev/null");
    EXPECT_NE(atlas.find("/4 frames"), std::string::npos) << atlas;
}

TEST(ProgressCli, CheckSaysWhatItVerified) {
    auto r = run_cli("analyze --check " + shq(example("art")) + " --no-cache -o /dev/null");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("check passed: 10 images"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("non-transparent texels"), std::string::npos) << r.err;
    auto q = run_cli("analyze --check -q " + shq(example("art")) + " --no-cache -o /dev/null");
    EXPECT_EQ(q.err, "");
}

TEST(OptimizeCli, OnATerminalSaysWhereOutputGoes) {
    if (!have_script()) GTEST_SKIP() << "no `script` (util-linux) to make a pseudo-terminal";
    const std::string tty = on_terminal("optimize " + shq(example("meadow.json")) + " --no-cache");
    EXPECT_NE(tty.find("not printed on a terminal"), std::string::npos) << tty;
    EXPECT_EQ(tty.find("\"draws\""), std::string::npos) << "JSON dumped on the terminal";
    // A pipe still gets the JSON.
    auto piped = run_cli("optimize " + shq(example("meadow.json")) + " --no-cache");
    ASSERT_EQ(piped.status, 0);
    EXPECT_NE(piped.out.find("\"draws\""), std::string::npos);
}

TEST(RenderCli, RefusesAFrameLargerThanItCanDraw) {
    fs::path dir = scratch("wide");
    std::string scene = "{\"images\": [{\"id\": \"t\", \"path\": \"" + example("art/tree.png") + "\"}], \"elements\": [";
    for (int i = 0; i < 41; ++i)
        scene += std::string(i ? "," : "") + "{\"image\": \"t\", \"transform\": [1, 0, 0, 1, " + std::to_string(i * 1000) + ", 0]}";
    scene += "]}";
    std::ofstream(dir / "wide.json") << scene;
    auto r = run_cli("render " + shq(dir / "wide.json") + " --no-cache -o " + shq(dir / "w.png"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("more than the 16384x96 frame"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--viewport"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "w.png"));
    auto part = run_cli("render " + shq(dir / "wide.json") + " --no-cache --viewport 0,0,2000,100 -o " + shq(dir / "w.png"));
    ASSERT_EQ(part.status, 0) << part.err;
    EXPECT_NE(part.err.find("over all 2000x100 viewport pixels"), std::string::npos) << part.err;
    EXPECT_NE(part.err.find("% of them covered"), std::string::npos) << part.err;
}
