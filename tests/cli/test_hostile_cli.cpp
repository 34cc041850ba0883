// The command line under hostile and careless use (issue 11): usage errors
// exit 2, non-finite numbers are refused, an output never overwrites an
// input, --no-cache writes no cache, and every error is one line.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "cli/run_cli.h"

using depthcull::test::example;
using depthcull::test::run_cli;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) { return depthcull::test::scratch_dir("hostile_" + name); }

const auto& shq = depthcull::test::shell_quote;

const auto& read = depthcull::test::read_bytes;

bool one_line(const std::string& err) { return !err.empty() && err.find('\n') == err.size() - 1; }

TEST(HostileCli, UsageErrorsExitTwo) {
    // CLI11's own codes were 105-109.
    EXPECT_EQ(run_cli("").status, 2);                                   // no subcommand
    EXPECT_EQ(run_cli("optimize").status, 2);                           // missing scene
    EXPECT_EQ(run_cli("optimize x.json --bogus").status, 2);            // unknown option
    EXPECT_EQ(run_cli("optimize x.json --max-vertices 2").status, 2);   // out of range
    EXPECT_EQ(run_cli("optimize x.json --opaque nope").status, 2);      // not a choice
    EXPECT_EQ(run_cli("optimize x.json --max-opaque x").status, 2);     // not a number
    // One line, worded as every other error (CLI11 printed two, unprefixed).
    for (const char* args : {"", "optimize", "optimize x.json --bogus", "render x.json --viewport 0,0,64"}) {
        auto r = run_cli(args);
        EXPECT_TRUE(one_line(r.err)) << args << ": " << r.err;
        EXPECT_EQ(r.err.rfind("depthcull: error: ", 0), 0u) << args << ": " << r.err;
    }
    EXPECT_EQ(run_cli("optimize x.json --bogus").err,
              "depthcull: error: The following argument was not expected: --bogus (depthcull optimize --help lists the options)\n");
    EXPECT_EQ(run_cli("--help").status, 0);
    EXPECT_NE(run_cli("--help").out.find("Exit status"), std::string::npos);
    EXPECT_EQ(run_cli("--version").status, 0);
    // An input error is 1.
    auto missing = run_cli("optimize /nonexistent/x.json --no-cache");
    EXPECT_EQ(missing.status, 1);
    EXPECT_TRUE(one_line(missing.err)) << missing.err;
}

TEST(HostileCli, NonFiniteNumbersAreUsageErrors) {
    const std::string scene = shq(example("meadow.json"));
    for (const char* viewport : {"nan,nan,64,64", "inf,0,64,64", "0,-inf,64,64", "1e300,0,64,64", "0,0,64,nan"}) {
        for (const char* command : {"optimize", "import", "render"}) {
            auto r = run_cli(std::string(command) + " " + scene + " --no-cache --viewport " + viewport + " -o /dev/null");
            EXPECT_EQ(r.status, 2) << command << " " << viewport << ": " << r.err;
            EXPECT_NE(r.err.find("--viewport"), std::string::npos) << r.err;
        }
    }
    for (const char* coverage : {"nan", "inf", "-nan"}) {
        auto r = run_cli("optimize " + scene + " --no-cache --min-coverage " + coverage);
        EXPECT_EQ(r.status, 2) << coverage << ": " << r.err;
    }
}

TEST(HostileCli, AnOutputNeverOverwritesAnInput) {
    fs::path dir = scratch("same");
    fs::copy(example("art"), dir / "art");
    fs::copy_file(example("meadow.json"), dir / "meadow.json");
    const std::string before = read(dir / "meadow.json");
    // The scene itself, by another spelling, and one of its images.
    for (const std::string& out : {std::string("meadow.json"), std::string("./art/../meadow.json"), std::string("art/rock.png")}) {
        auto r = run_cli("import " + shq(dir / "meadow.json") + " -o " + shq(dir / out));
        EXPECT_EQ(r.status, 1) << out;
        EXPECT_NE(r.err.find("refusing to overwrite an input"), std::string::npos) << r.err;
        EXPECT_TRUE(one_line(r.err)) << r.err;
        auto o = run_cli("optimize " + shq(dir / "meadow.json") + " --no-cache -o " + shq(dir / out));
        EXPECT_EQ(o.status, 1) << out;
    }
    EXPECT_EQ(read(dir / "meadow.json"), before);
    // Two outputs naming one file, neither existing yet.
    auto both = run_cli("optimize " + shq(dir / "meadow.json") + " --no-cache -o " + shq(dir / "x") + " --binary " + shq(dir / "art/../x"));
    EXPECT_EQ(both.status, 1);
    EXPECT_NE(both.err.find("two outputs name the same file"), std::string::npos) << both.err;
    EXPECT_FALSE(fs::exists(dir / "x"));
    // Different files are fine.
    EXPECT_EQ(run_cli("optimize " + shq(dir / "meadow.json") + " --no-cache -o " + shq(dir / "x") + " --binary " + shq(dir / "y")).status, 0);
    fs::remove_all(dir);
}

TEST(HostileCli, NoCacheWritesNoCache) {
    fs::path dir = scratch("nocache");
    fs::path home = dir / "home";
    fs::create_directories(home);
    const std::string env = "env HOME=" + shq(home) + " XDG_CACHE_HOME=" + shq(home / ".cache") + " ";
    // run_cli puts the binary first; the environment goes through `env`.
    auto r = run_cli("optimize " + shq(example("meadow.json")) + " --no-cache -o " + shq(dir / "m.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    std::string cmd = env + "'" + DEPTHCULL_CLI_PATH + "' optimize " + shq(example("meadow.json")) + " --no-cache -o " + shq(dir / "n.json") +
                      " 2>/dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    EXPECT_FALSE(fs::exists(home / ".cache")) << "something was written under the cache home";
    // And with the cache, it is written there (the test sees the right place).
    cmd = env + "'" + DEPTHCULL_CLI_PATH + "' optimize " + shq(example("meadow.json")) + " -o " + shq(dir / "c.json") + " 2>/dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    EXPECT_TRUE(fs::exists(home / ".cache" / "depthcull" / "analysis"));
    // A relative XDG_CACHE_HOME is ignored (the XDG spec): it made a cache
    // under the directory the run was in.
    fs::remove_all(home / ".cache");
    cmd = "cd " + shq(dir) + " && env HOME=" + shq(home) + " XDG_CACHE_HOME=relative '" + DEPTHCULL_CLI_PATH + "' optimize " +
          shq(example("meadow.json")) + " -o " + shq(dir / "r.json") + " 2>/dev/null";
    ASSERT_EQ(std::system(cmd.c_str()), 0);
    EXPECT_FALSE(fs::exists(dir / "relative"));
    EXPECT_TRUE(fs::exists(home / ".cache" / "depthcull" / "analysis"));
    fs::remove_all(dir);
}

} // namespace
