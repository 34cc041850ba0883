// Outputs never clobber (issue 21, points 4 and 8): a device, FIFO or link
// named as an output is written through, never replaced; previews and
// Godot scenes never replace an input or each other; a failed run writes
// none of its outputs; long names fit; RLIMIT_FSIZE is an error, not a
// signal; a frame too large to draw is refused by name. Tests that need
// /dev/null or /dev/stdout use a link to it made here, so no run can ever
// replace the real one (these tests run as root in CI).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include <sys/stat.h>
#include <sys/types.h>

#include "cli/run_cli.h"
#include "depthcull/io.h"

using depthcull::test::example;
using depthcull::test::run_cli;
namespace fs = std::filesystem;

namespace {

const auto& shq = depthcull::test::shell_quote;
const auto& read = depthcull::test::read_bytes;

fs::path scratch(const std::string& name) { return depthcull::test::scratch_dir("outputs_" + name); }

bool is_char_device(const char* path) {
    struct stat st;
    return ::lstat(path, &st) == 0 && S_ISCHR(st.st_mode);
}

bool named_pipe(const fs::path& path) {
    struct stat st;
    return ::lstat(path.c_str(), &st) == 0 && S_ISFIFO(st.st_mode);
}

// Files left in `dir` (recursively), as paths relative to it.
std::set<std::string> files_in(const fs::path& dir) {
    std::set<std::string> names;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (!fs::is_directory(e.symlink_status())) names.insert(e.path().lexically_relative(dir).string());
    return names;
}

// A 4x4 PNG, its texels all `value` (distinct images for distinct values).
void write_test_png(const fs::path& path, std::uint8_t value) {
    depthcull::Image image;
    image.width = image.height = 4;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) image.rgba.insert(image.rgba.end(), {value, value, value, std::uint8_t(x < 2 ? 255 : 0)});
    depthcull::io::write_png(path.string(), image.view());
}

// A TexturePacker hash atlas of `frames` (each the same 4x4 cell) on
// page `page` (an image path relative to the JSON).
void write_atlas(const fs::path& json, const std::string& page, const std::vector<std::string>& frames) {
    std::string text = "{\"frames\": {";
    for (std::size_t i = 0; i < frames.size(); ++i)
        text += (i ? "," : "") + std::string("\"") + frames[i] +
                "\": {\"frame\": {\"x\": 0, \"y\": 0, \"w\": 4, \"h\": 4}, \"rotated\": false, \"trimmed\": false, "
                "\"spriteSourceSize\": {\"x\": 0, \"y\": 0, \"w\": 4, \"h\": 4}, \"sourceSize\": {\"w\": 4, \"h\": 4}}";
    text += "}, \"meta\": {\"image\": \"" + page + "\", \"size\": {\"w\": 4, \"h\": 4}, \"scale\": \"1\"}}";
    std::ofstream(json) << text;
}

std::string scene() { return shq(example("meadow.json")); }

TEST(OutputsCli, AFifoIsWrittenInPlace) {
    const fs::path dir = scratch("fifo");
    const fs::path fifo = dir / "pipe", got = dir / "got.json";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    // The reader in the background; the timeout ends it if no writer comes.
    const std::string command = "(timeout 60 cat " + shq(fifo) + " > " + shq(got) + " &) ; '" DEPTHCULL_CLI_PATH "' import " + scene() +
                                " -o " + shq(fifo) + " 2>/dev/null; status=$?; sleep 0.2; exit $status";
    EXPECT_EQ(std::system(command.c_str()), 0);
    EXPECT_TRUE(named_pipe(fifo)) << "the FIFO was replaced";
    for (int i = 0; i < 50 && read(got).find("\"elements\"") == std::string::npos; ++i) ::usleep(100000);
    EXPECT_NE(read(got).find("\"elements\""), std::string::npos);
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"got.json", "pipe"}));
}

TEST(OutputsCli, ALinkToDevNullStaysALinkToACharacterDevice) {
    const fs::path dir = scratch("devnull");
    fs::create_symlink("/dev/null", dir / "null");
    fs::create_symlink("/dev/null", dir / "null2");
    for (const std::string& command : {"import " + scene() + " -o " + shq(dir / "null"),
                                       "optimize " + scene() + " --no-cache -q -o " + shq(dir / "null") + " --binary " + shq(dir / "null2")}) {
        auto r = run_cli(command);
        EXPECT_EQ(r.status, 0) << command << ": " << r.err;
        EXPECT_TRUE(fs::is_symlink(dir / "null")) << command;
        EXPECT_TRUE(fs::is_symlink(dir / "null2")) << command;
        EXPECT_TRUE(is_char_device("/dev/null"));
        EXPECT_EQ(files_in(dir), (std::set<std::string>{"null", "null2"})) << command;
    }
}

TEST(OutputsCli, ALinkIsFollowedAndItsTargetReplaced) {
    const fs::path dir = scratch("link");
    std::ofstream(dir / "real.json") << "old";
    fs::create_symlink("real.json", dir / "link.json");
    auto r = run_cli("import " + scene() + " -o " + shq(dir / "link.json"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::is_symlink(dir / "link.json"));
    EXPECT_NE(read(dir / "real.json").find("\"elements\""), std::string::npos);
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"link.json", "real.json"}));
}

TEST(OutputsCli, ALinkToDevStdoutWritesThisProcessesStdout) {
    const fs::path dir = scratch("stdout");
    fs::create_symlink("/dev/stdout", dir / "out");
    auto r = run_cli("import " + scene() + " -o " + shq(dir / "out"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("\"elements\""), std::string::npos);
    EXPECT_TRUE(fs::is_symlink(dir / "out"));
    // Behind a shell's >> the file is appended to, not replaced.
    std::ofstream(dir / "log") << "first\n";
    r = run_cli("import " + scene() + " -o " + shq(dir / "out") + " >> " + shq(dir / "log"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(read(dir / "log").rfind("first\n{", 0), 0u);
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"log", "out"}));
}

TEST(OutputsCli, AFailedWriteToStdoutIsAnError) {
    auto r = run_cli("import " + scene() + " > /dev/full");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("stdout: write failed (No space left on device)"), std::string::npos) << r.err;
}

// Files were renamed into place before stdout was written: a run whose
// stdout failed (a full disk, a closed pipe) left them behind.
TEST(OutputsCli, AFailedStreamLeavesNoFileOfTheRun) {
    const fs::path dir = scratch("failed_stream");
    auto r = run_cli("optimize " + scene() + " --no-cache -q -o - --binary " + shq(dir / "m.bin") + " > /dev/full");
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("stdout: write failed"), std::string::npos) << r.err;
    write_test_png(dir / "a.png", 10);
    r = run_cli("analyze " + shq(dir / "a.png") + " --no-cache -q --preview " + shq(dir / "pv") + " > /dev/full");
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"a.png"}));
}

TEST(OutputsCli, PreviewsNeverReplaceTheInputs) {
    const fs::path dir = scratch("preview_inputs");
    write_test_png(dir / "a.png", 10);
    write_test_png(dir / "b.png", 20);
    const std::string a = read(dir / "a.png"), b = read(dir / "b.png");
    auto r = run_cli("analyze " + shq(dir) + " --no-cache -q --preview " + shq(dir) + " -o " + shq(dir / "out.json"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("refusing to overwrite an input"), std::string::npos) << r.err;
    EXPECT_EQ(read(dir / "a.png"), a);
    EXPECT_EQ(read(dir / "b.png"), b);
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"a.png", "b.png"})); // no out.json, no .svg

    // atlas --preview into the page's directory: the page preview would be sheet.png.
    write_test_png(dir / "sheet.png", 30);
    write_atlas(dir / "sheet.json", "sheet.png", {"x.png"});
    const std::string page = read(dir / "sheet.png");
    r = run_cli("atlas " + shq(dir / "sheet.json") + " --no-cache -q --preview " + shq(dir) + " -o " + shq(dir / "out.json"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("refusing to overwrite an input"), std::string::npos) << r.err;
    EXPECT_EQ(read(dir / "sheet.png"), page);
    EXPECT_FALSE(fs::exists(dir / "out.json"));
}

// Files read through the scene (an external tileset, an object template, a
// scene's atlas) and the --target profile are inputs too: each was
// replaced by an output that named it, with exit status 0.
TEST(OutputsCli, FilesReadThroughTheSceneAndTheProfileAreInputs) {
    const fs::path dir = scratch("documents");
    const fs::path data = fs::path(DEPTHCULL_SOURCE_DIR) / "tests/data/tiled";
    for (const char* name : {"template.tmx", "tile.tx", "tiles.tsx", "tiles.png"}) fs::copy_file(data / name, dir / name);
    write_test_png(dir / "sheet.png", 30);
    write_atlas(dir / "sheet.json", "sheet.png", {"x.png"});
    std::ofstream(dir / "s.json") << R"({"viewport": {"x": 0, "y": 0, "width": 8, "height": 8},
        "images": [{"id": "a", "atlas": "sheet.json"}], "elements": [{"image": "a", "frame": "x.png"}]})";
    fs::copy_file(fs::path(DEPTHCULL_SOURCE_DIR) / "bench/results/ideal-frame/profile-fit-xeon.json", dir / "p.json");
    const std::set<std::string> before = files_in(dir);
    std::map<std::string, std::string> bytes;
    for (const std::string& name : before) bytes[name] = read(dir / name);
    const std::string map = shq(dir / "template.tmx");
    for (const std::string& command :
         {"import " + map + " -o " + shq(dir / "tiles.tsx"), "import " + map + " -o " + shq(dir / "tile.tx"),
          "optimize " + map + " --no-cache -q -o " + shq(dir / "tile.tx"), "optimize " + shq(dir / "s.json") + " --no-cache -q -o " + shq(dir / "sheet.json"),
          "optimize " + shq(dir / "s.json") + " --no-cache -q --target " + shq(dir / "p.json") + " -o " + shq(dir / "p.json"),
          "optimize " + shq(dir / "s.json") + " --no-cache -q --target " + shq(dir / "p.json") + " -o - --binary " + shq(dir / "p.json"),
          "analyze " + shq(dir / "sheet.png") + " --no-cache -q --target " + shq(dir / "p.json") + " -o " + shq(dir / "p.json")}) {
        auto r = run_cli(command);
        EXPECT_EQ(r.status, 1) << command;
        EXPECT_NE(r.err.find("refusing to overwrite an input"), std::string::npos) << command << ": " << r.err;
    }
    EXPECT_EQ(files_in(dir), before);
    for (const std::string& name : before) EXPECT_EQ(read(dir / name), bytes[name]) << name;
}

TEST(OutputsCli, PreviewNamesAreDistinct) {
    const fs::path dir = scratch("preview_names");
    fs::create_directories(dir / "x");
    fs::create_directories(dir / "y");
    write_test_png(dir / "x" / "a.png", 10);
    write_test_png(dir / "y" / "a.png", 20);
    write_test_png(dir / "A.png", 30);
    write_test_png(dir / "a-2.png", 40);
    auto r = run_cli("analyze " + shq(dir / "x" / "a.png") + " " + shq(dir / "y" / "a.png") + " " + shq(dir / "A.png") + " " +
                     shq(dir / "a-2.png") + " --no-cache -q --preview " + shq(dir / "p") + " -o " + shq(dir / "out.json"));
    EXPECT_EQ(r.status, 0) << r.err;
    // Four inputs, four pairs, distinct even ignoring case.
    std::set<std::string> folded;
    for (const std::string& name : files_in(dir / "p")) {
        std::string f = name;
        for (char& c : f) c = char(std::tolower(static_cast<unsigned char>(c)));
        folded.insert(f);
    }
    EXPECT_EQ(folded.size(), 8u);
    EXPECT_EQ(files_in(dir / "p").size(), 8u);
}

TEST(OutputsCli, GodotScenesAndPagePreviewsAreDistinct) {
    const fs::path dir = scratch("godot_names");
    write_test_png(dir / "sheet.png", 10);
    write_atlas(dir / "sheet.json", "sheet.png", {"a.png", "a.jpg", "a-2"});
    auto r = run_cli("atlas " + shq(dir / "sheet.json") + " --no-cache -q --godot " + shq(dir / "godot") + " -o " + shq(dir / "out.json"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(files_in(dir / "godot"), (std::set<std::string>{"a.tscn", "a-2.tscn", "a-3.tscn"}));

    // A multipack whose two pages are both named sheet.png.
    fs::create_directories(dir / "one");
    fs::create_directories(dir / "two");
    write_test_png(dir / "one" / "sheet.png", 20);
    write_test_png(dir / "two" / "sheet.png", 30);
    const std::string frame = "{\"filename\": \"%s\", \"frame\": {\"x\": 0, \"y\": 0, \"w\": 4, \"h\": 4}, \"rotated\": false, "
                              "\"trimmed\": false, \"spriteSourceSize\": {\"x\": 0, \"y\": 0, \"w\": 4, \"h\": 4}, "
                              "\"sourceSize\": {\"w\": 4, \"h\": 4}}";
    auto texture = [&](const std::string& image, const std::string& name) {
        std::string f = frame;
        f.replace(f.find("%s"), 2, name);
        return "{\"image\": \"" + image + "\", \"format\": \"RGBA8888\", \"size\": {\"w\": 4, \"h\": 4}, \"scale\": 1, \"frames\": [" + f + "]}";
    };
    std::ofstream(dir / "multi.json") << "{\"textures\": [" + texture("one/sheet.png", "p.png") + "," + texture("two/sheet.png", "q.png") +
                                             "], \"meta\": {\"app\": \"test\"}}";
    r = run_cli("atlas " + shq(dir / "multi.json") + " --no-cache -q --preview " + shq(dir / "pv") + " -o " + shq(dir / "multi-out.json"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / "pv" / "sheet.png"));
    EXPECT_TRUE(fs::exists(dir / "pv" / "sheet-2.png"));
}

TEST(OutputsCli, LongNamesFitAndAFailedRunWritesNothing) {
    const fs::path dir = scratch("long");
    // A legal 250-byte output name: its temporary must fit NAME_MAX too.
    const std::string long_name(245, 'o');
    auto r = run_cli("import " + scene() + " -o " + shq(dir / (long_name + ".json")));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(fs::exists(dir / (long_name + ".json")));
    fs::remove(dir / (long_name + ".json"));

    // A frame name of 300 bytes: its preview and Godot names are cut.
    write_test_png(dir / "sheet.png", 10);
    write_atlas(dir / "sheet.json", "sheet.png", {std::string(300, 'f') + ".png", "g.png"});
    r = run_cli("atlas " + shq(dir / "sheet.json") + " --no-cache -q -j 1 --preview " + shq(dir / "pv") + " --godot " + shq(dir / "gd") +
                " -o " + shq(dir / "out.json"));
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(files_in(dir / "gd").size(), 2u);
    EXPECT_EQ(files_in(dir / "pv").size(), 6u); // the page and two frames, PNG and SVG
    for (const auto& name : files_in(dir / "pv")) EXPECT_LE(fs::path(name).filename().string().size(), 255u);

    // A run that fails on its second image leaves neither the first's
    // previews nor the JSON behind.
    const fs::path run = dir / "run";
    fs::create_directories(run);
    write_test_png(run / "a.png", 10);
    std::ofstream(run / "b.png") << "not a PNG";
    r = run_cli("analyze " + shq(run / "a.png") + " " + shq(run / "b.png") + " --no-cache -q -j 1 --preview " + shq(dir / "pv2") +
                " -o " + shq(dir / "run.json"));
    EXPECT_EQ(r.status, 1);
    EXPECT_FALSE(fs::exists(dir / "run.json"));
    EXPECT_TRUE(!fs::exists(dir / "pv2") || files_in(dir / "pv2").empty());
}

TEST(OutputsCli, ADirectoryOrSocketIsNotAnOutput) {
    const fs::path dir = scratch("refused");
    fs::create_directories(dir / "d");
    auto r = run_cli("import " + scene() + " -o " + shq(dir / "d"));
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("is a directory"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::is_directory(dir / "d"));
}

TEST(OutputsCli, FileTooLargeIsAnErrorAndLeavesNoTemporary) {
    const fs::path dir = scratch("fsize");
    // ulimit -f counts 1024-byte blocks: the scene JSON is larger than 1 KB.
    const std::string command = "ulimit -f 1; '" DEPTHCULL_CLI_PATH "' import " + scene() + " -o " + shq(dir / "out.json") + " 2> " +
                                shq(dir / "err");
    const int status = std::system(("bash -c " + shq(command)).c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << status;
    EXPECT_NE(read(dir / "err").find("out.json: write failed (File too large)"), std::string::npos) << read(dir / "err");
    EXPECT_EQ(files_in(dir), (std::set<std::string>{"err"}));
}

TEST(OutputsCli, AFrameOverKMaxFramePixelsIsRefusedByName) {
    auto r = run_cli("render " + scene() + " --no-cache --viewport 0,0,16384,16384 -o /nonexistent/frame.png");
    if (r.err.find("built without the renderer") != std::string::npos) GTEST_SKIP() << r.err;
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find("meadow.json: the 16384x16384 frame"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("kMaxFramePixels"), std::string::npos) << r.err;
}

} // namespace
