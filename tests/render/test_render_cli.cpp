// `depthcull render` and `depthcull bench` on the bundled example scene,
// end to end. Skips where the CLI is not built or no GL context exists.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <sys/wait.h>
#include <unistd.h>

#include "depthcull/render.h"
#include "testing/corpus.h"

namespace depthcull {
namespace {

namespace fs = std::filesystem;

struct CliRun {
    int status = -1;
    std::string output;
};

// env: "NAME=value " put before the command.
CliRun run_cli(const std::string& args, const std::string& env = {}) {
    const fs::path out = fs::temp_directory_path() / ("depthcull_render_cli_" + std::to_string(::getpid()) + ".txt");
    const std::string command = env + std::string("\"") + DEPTHCULL_CLI_PATH + "\" " + args + " > \"" + out.string() + "\" 2>&1";
    CliRun run;
    run.status = std::system(command.c_str());
    std::ifstream in(out);
    std::stringstream text;
    text << in.rdbuf();
    run.output = text.str();
    fs::remove(out);
    return run;
}

std::string skip_reason() {
    if (std::string(DEPTHCULL_CLI_PATH).empty() || !fs::exists(DEPTHCULL_CLI_PATH)) return "depthcull CLI not built";
    if (!fs::exists(test::source_path("examples/meadow.json"))) return "examples/meadow.json missing";
    try {
        render::GlRenderer::create({});
    } catch (const render::NoContext& e) {
        return e.what();
    }
    return {};
}

TEST(RenderCli, ComparesWithOverpaintAndWritesPictures) {
    if (auto why = skip_reason(); !why.empty()) GTEST_SKIP() << why;
    const fs::path dir = fs::temp_directory_path() / ("depthcull_render_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string scene = test::source_path("examples/meadow.json");
    CliRun r = run_cli("render \"" + scene + "\" --no-cache --mode optimized --compare -o \"" + (dir / "frame.png").string() +
                    "\" --heatmap \"" + (dir / "heat.png").string() + "\"");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_TRUE(fs::exists(dir / "frame.png"));
    EXPECT_TRUE(fs::exists(dir / "heat.png"));
    // Nearest filtering: not one pixel may differ (any difference exits 1).
    EXPECT_NE(r.output.find("equals the overpaint frame pixel for pixel"), std::string::npos) << r.output;
    r = run_cli("render \"" + scene + "\" --no-cache --mode meshes --compare");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("equals the overpaint frame pixel for pixel"), std::string::npos) << r.output;

    r = run_cli("render \"" + scene + "\" --no-cache");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("nothing to do"), std::string::npos) << r.output;
    r = run_cli("render \"" + (dir / "missing.json").string() + "\" --no-cache --compare");
    EXPECT_NE(r.status, 0);
    fs::remove_all(dir);
}

TEST(BenchCli, PrintsTableTwoAsJson) {
    if (auto why = skip_reason(); !why.empty()) GTEST_SKIP() << why;
    const std::string scene = test::source_path("examples/meadow.json");
    CliRun r = run_cli("bench \"" + scene + "\" --no-cache --frames 2 --warmup 0 --json");
    ASSERT_EQ(r.status, 0) << r.output;
    for (const char* key : {"\"overpaint\"", "\"meshes\"", "\"optimized\"", "\"ideal_overdraw\"", "\"samples_passed\"",
                            "\"fragments_rasterized\"", "\"fragments_shaded\"", "\"cpu_ms_median\"", "\"shader\": \"runtime\""})
        EXPECT_NE(r.output.find(key), std::string::npos) << key;
    // The runtime renderer's frames equal its overpaint frame off texel edges.
    std::size_t equal = 0;
    for (std::size_t at = 0; (at = r.output.find("\"pixels_differ_elsewhere\": 0,", at)) != std::string::npos; ++at) ++equal;
    EXPECT_EQ(equal, 3u) << r.output;
    r = run_cli("bench \"" + scene + "\" --no-cache --frames 1 --warmup 0 --renderer instrumented");
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("instrumented shader"), std::string::npos) << r.output;
    r = run_cli("bench \"" + scene + "\" --no-cache --frames 1 --renderer bogus");
    EXPECT_NE(r.status, 0);
    r = run_cli("bench \"" + scene + "\" --no-cache --frames 1 --modes optimized,bogus");
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find("unknown mode 'bogus'"), std::string::npos) << r.output;
}

// Without an OpenGL context (EGL given no vendor library, see
// GlRenderDeathTest) render, bench and calibrate stop with one line: what
// render::NoContext says and how to install Mesa, exit status 1.
TEST(RenderCli, NoOpenGlContextIsOneLineAndExitOne) {
    if (std::string(DEPTHCULL_CLI_PATH).empty() || !fs::exists(DEPTHCULL_CLI_PATH)) GTEST_SKIP() << "depthcull CLI not built";
    const std::string scene = test::source_path("examples/meadow.json");
    const std::string env = "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent/depthcull_no_egl_vendor.json ";
    for (const std::string& args : {"render \"" + scene + "\" --no-cache --gl device --compare",
                                    "bench \"" + scene + "\" --no-cache --gl device --frames 1 --warmup 0",
                                    "bench \"" + scene + "\" --no-cache --frames 1 --warmup 0 --renderer instrumented",
                                    std::string("calibrate --quick --gl surfaceless -o -")}) {
        const CliRun r = run_cli(args, env);
        ASSERT_TRUE(WIFEXITED(r.status)) << args;
        EXPECT_EQ(WEXITSTATUS(r.status), 1) << args << "\n" << r.output;
        EXPECT_EQ(r.output.rfind("depthcull: error: no OpenGL context: ", 0), 0u) << args << "\n" << r.output;
        EXPECT_NE(r.output.find("(headless rendering needs Mesa's EGL: apt-get install libegl-mesa0 libgl1-mesa-dri)\n"),
                  std::string::npos)
            << r.output;
        EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << "\n" << r.output;
    }
    const CliRun r = run_cli("optimize \"" + scene + "\" --no-cache --target auto -o -", env);
    EXPECT_EQ(r.status, 1 << 8) << r.output;
    EXPECT_EQ(r.output.rfind("depthcull: error: --target auto: no OpenGL renderer found (no OpenGL context: ", 0), 0u) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
}

} // namespace
} // namespace depthcull
