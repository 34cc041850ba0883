// scripts/fit-profile's saved frames (--save / --load, issue 25's block
// model): a file it did not write, or could not read as frames (a FIFO,
// over 64 MiB, nested past Python's stack, NaN), is one line
// on stderr and exit 1; --save replaces no non-regular file and not the
// file --load reads, and leaves no temporary file behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <sys/stat.h>

#include "cli/run_cli.h"

namespace fs = std::filesystem;
using depthcull::test::read_bytes;
using depthcull::test::run_command;
using depthcull::test::shell_quote;

namespace {

depthcull::test::CliResult fit_profile(const std::string& args) {
    return run_command("python3 " + shell_quote(fs::path(DEPTHCULL_SOURCE_DIR) / "scripts" / "fit-profile") + " " + args);
}

bool one_line(const std::string& err) { return !err.empty() && err.find('\n') == err.size() - 1; }

// Frames of made-up cameras whose CPU ms are a sum of their features, so the
// fit has a solution; `blocks` adds the block counts bench reports.
std::string frames(bool blocks) {
    std::string out = "[";
    for (int k = 0; k < 12; ++k) {
        const double tri = 100 + 37 * k, blend = 1e5 * (1 + k % 5), opaque = 5e4 * (k % 3), rejected = 1e3 * (k % 4);
        const double ms = 0.01 + tri * 0.13e-3 + blend * 4.8e-6 + opaque * 4e-6 + rejected * 3.5e-6 + tri * 40 * 6.8e-6;
        out += std::string(k ? "," : "") + "[{\"pixels\": 786432, \"depth_clear\": " + (k % 2 ? "true" : "false") +
               ", \"draw_calls\": " + std::to_string(10 + k) + ", \"texture_switches\": " + std::to_string(3 + k % 4) +
               ", \"triangles\": " + std::to_string(tri) + ", \"triangle_perimeter\": " + std::to_string(tri * 40) +
               ", \"opaque_fragments\": " + std::to_string(opaque) + ", \"blend_fragments\": " + std::to_string(blend) +
               ", \"rejected_fragments\": " + std::to_string(rejected) +
               (blocks ? ", \"opaque_blocks\": " + std::to_string(opaque / 14) + ", \"blend_blocks\": " + std::to_string(blend / 13) : "") +
               "}, " + std::to_string(ms) + "]";
    }
    return out + "]";
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

TEST(FitProfileCli, LoadsWhatItSavesAndFitsBlocks) {
    const fs::path dir = depthcull::test::scratch_dir("fit_profile_good");
    write(dir / "frames.json", frames(true));
    auto r = fit_profile("--load " + shell_quote(dir / "frames.json") + " --blocks --save " + shell_quote(dir / "again.json"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("\"depthcull_profile\": 1"), std::string::npos) << r.out;
    EXPECT_NE(r.err.find("block model: median |error|"), std::string::npos) << r.err;
    // What --save wrote loads again to the same fit.
    auto again = fit_profile("--load " + shell_quote(dir / "again.json"));
    ASSERT_EQ(again.status, 0) << again.err;
    EXPECT_EQ(again.out.substr(again.out.find("\"frame_us\"")), r.out.substr(r.out.find("\"frame_us\"")));
    for (const auto& entry : fs::directory_iterator(dir)) EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
    fs::remove_all(dir);
}

TEST(FitProfileCli, RefusesFilesItCannotFitInOneLine) {
    const fs::path dir = depthcull::test::scratch_dir("fit_profile_bad");
    write(dir / "nan.json", "[[{\"pixels\": NaN}, 1]]");
    write(dir / "huge.json", "[[{\"pixels\": 1e999}, 1]]");
    write(dir / "shape.json", "{\"frames\": []}");
    write(dir / "negative.json", "[[{}, -1]]");
    write(dir / "nested.json", std::string(100000, '[') + std::string(100000, ']'));
    write(dir / "old.json", frames(false));
    ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0); // opened for reading, it would block
    write(dir / "big.json", std::string((64 << 20) + 1, ' '));
    for (const fs::path& p : {dir / "missing.json", dir, fs::path("/dev/null"), dir / "fifo", dir / "big.json", dir / "nan.json",
                              dir / "huge.json", dir / "shape.json", dir / "negative.json", dir / "nested.json"}) {
        auto r = fit_profile("--load " + shell_quote(p));
        EXPECT_EQ(r.status, 1) << p;
        EXPECT_TRUE(one_line(r.err)) << p << ": " << r.err;
        EXPECT_NE(r.err.find("fit-profile: --load"), std::string::npos) << r.err;
    }
    // Frames measured before bench counted blocks fit, but not with --blocks.
    EXPECT_EQ(fit_profile("--load " + shell_quote(dir / "old.json")).status, 0);
    auto r = fit_profile("--load " + shell_quote(dir / "old.json") + " --blocks");
    EXPECT_EQ(r.status, 1);
    EXPECT_TRUE(one_line(r.err)) << r.err;
    fs::remove_all(dir);
}

TEST(FitProfileCli, SaveReplacesNoInputAndNoNonRegularFile) {
    const fs::path dir = depthcull::test::scratch_dir("fit_profile_save");
    write(dir / "frames.json", frames(true));
    const std::string before = read_bytes(dir / "frames.json");
    fs::create_directory(dir / "folder");
    for (const fs::path& out : {dir / "frames.json", fs::path("/dev/null"), dir / "folder"}) {
        auto r = fit_profile("--load " + shell_quote(dir / "frames.json") + " --save " + shell_quote(out));
        EXPECT_EQ(r.status, 2) << out;
        EXPECT_NE(r.err.find("--save"), std::string::npos) << r.err;
    }
    EXPECT_EQ(read_bytes(dir / "frames.json"), before);
    EXPECT_TRUE(fs::is_directory(dir / "folder"));
    // Neither --target nor --load: a usage error.
    EXPECT_EQ(fit_profile("").status, 2);
    fs::remove_all(dir);
}

} // namespace
