// Runs the depthcull binary in a shell and captures what it printed.
#pragma once

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

namespace depthcull::test {

struct CliResult {
    int status = -1;
    std::string out, err;
};

// `command` is a shell command line; stderr is captured apart.
inline CliResult run_command(const std::string& command) {
    static int counter = 0;
    auto dir = std::filesystem::temp_directory_path();
    std::string errfile = (dir / ("dc_cli_err_" + std::to_string(::getpid()) + "_" + std::to_string(counter++))).string();
    std::string cmd = command + " 2>'" + errfile + "'";
    CliResult r;
    FILE* p = ::popen(cmd.c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf;
    std::size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
    int st = ::pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    std::ifstream in(errfile);
    std::stringstream ss;
    ss << in.rdbuf();
    r.err = ss.str();
    std::filesystem::remove(errfile);
    return r;
}

// `args` is shell syntax, appended to the binary's path.
inline CliResult run_cli(const std::string& args) { return run_command(std::string("'") + DEPTHCULL_CLI_PATH + "' " + args); }

// A fresh, empty directory for one test: temp/dc_<name>_<pid>.
inline std::filesystem::path scratch_dir(const std::string& name) {
    std::filesystem::path dir = std::filesystem::temp_directory_path() / ("dc_" + name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

// A path quoted for the shell command line run_cli builds.
inline std::string shell_quote(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

// A file's bytes ("" when it cannot be read).
inline std::string read_bytes(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

inline std::string example(const std::string& relative) { return std::string(DEPTHCULL_SOURCE_DIR) + "/examples/" + relative; }

} // namespace depthcull::test
