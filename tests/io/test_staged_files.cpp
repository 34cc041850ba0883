// A run's outputs staged, then committed together or not at all
// (depthcull/staged_files.h, issue 21): nothing is left when a run fails,
// temporaries fit NAME_MAX, links are followed, directories refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <unistd.h>

#include "depthcull/staged_files.h"

using namespace depthcull;
namespace fs = std::filesystem;

namespace {

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("dc_staged_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::size_t entries(const fs::path& dir) {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
    return n;
}

std::string read(const fs::path& p) {
    std::ifstream in(p);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(StagedFiles, NothingIsWrittenUnlessCommitted) {
    const fs::path dir = scratch("uncommitted");
    {
        io::StagedFiles files;
        files.stage((dir / "a.json").string(), "a");
        files.stage((dir / "b.json").string(), "b");
        EXPECT_EQ(entries(dir), 2u); // the two temporaries
    }
    EXPECT_EQ(entries(dir), 0u);
    {
        io::StagedFiles files;
        files.stage((dir / "a.json").string(), "a");
        EXPECT_THROW(files.stage((dir / "b.json").string(), [](const io::WriteBytes& write) {
            write("half");
            throw std::runtime_error("the run fails");
        }),
                     std::runtime_error);
    }
    EXPECT_EQ(entries(dir), 0u);
    io::StagedFiles files;
    files.stage((dir / "a.json").string(), "a");
    files.stage((dir / "b.json").string(), "b");
    files.commit();
    EXPECT_EQ(read(dir / "a.json"), "a");
    EXPECT_EQ(read(dir / "b.json"), "b");
    EXPECT_EQ(entries(dir), 2u);
}

TEST(StagedFiles, TemporariesFitNameMax) {
    const std::string name(255, 'n');
    EXPECT_LE(fs::path(io::temporary_name("/tmp/" + name, 2147483647L, ~0ull)).filename().string().size(), 255u);
    const fs::path dir = scratch("long");
    io::write_file_atomic((dir / std::string(250, 'x')).string(), "ok");
    EXPECT_EQ(read(dir / std::string(250, 'x')), "ok");
    EXPECT_THROW(io::resolve_output((dir / std::string(256, 'x')).string()), depthcull::Error);
}

TEST(StagedFiles, KindsOfOutput) {
    const fs::path dir = scratch("kinds");
    std::ofstream(dir / "real") << "old";
    fs::create_symlink("real", dir / "link");
    fs::create_symlink("/dev/null", dir / "null"); // never the real /dev/null itself
    fs::create_directories(dir / "d");
    EXPECT_EQ(io::resolve_output((dir / "new").string()).kind, io::OutputTarget::file);
    EXPECT_EQ(io::resolve_output((dir / "link").string()).target, (dir / "real").string());
    EXPECT_EQ(io::resolve_output((dir / "null").string()).kind, io::OutputTarget::in_place);
    EXPECT_EQ(io::resolve_output("-").kind, io::OutputTarget::descriptor);
    EXPECT_EQ(io::resolve_output("/dev/stdout").fd, 1);
    EXPECT_EQ(io::resolve_output("/proc/self/fd/2").fd, 2);
    EXPECT_THROW(io::resolve_output((dir / "d").string()), depthcull::Error);
    io::write_file_atomic((dir / "link").string(), "new");
    EXPECT_TRUE(fs::is_symlink(dir / "link"));
    EXPECT_EQ(read(dir / "real"), "new");
    io::write_file_atomic((dir / "null").string(), "gone");
    EXPECT_TRUE(fs::is_symlink(dir / "null"));
    EXPECT_EQ(entries(dir), 4u);
}

} // namespace
