#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <sys/stat.h>
#include <unistd.h>

#include "depthcull/io.h"
#include "depthcull/limits.h"
#include "depthcull/staged_files.h"
#include "io/formats.h"

namespace depthcull::io {

namespace fs = std::filesystem;

namespace {

// The system reads a name up to its first NUL: "blob.png\0.txt" (a JSON
// "\u0000") opened blob.png under another name.
void check_name(const std::string& path) {
    if (path.find('\0') == std::string::npos) return;
    std::string shown;
    for (char c : path) shown += c ? std::string(1, c) : std::string("\\0");
    throw Error(shown + ": a file name cannot hold a NUL character");
}

} // namespace

void check_input_file(const std::string& path) {
    check_name(path);
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) throw Error(path + ": cannot open (" + std::strerror(errno) + ")");
    if (S_ISDIR(st.st_mode)) throw Error(path + ": is a directory, expected a file");
    // /dev/zero, a FIFO or a socket would be read without end (or block).
    if (!S_ISREG(st.st_mode)) throw Error(path + ": not a regular file (devices, FIFOs and sockets are not read)");
    if (std::uint64_t(st.st_size) > limits::kMaxFileBytes)
        throw Error(path + ": file is larger than 1 GiB (kMaxFileBytes)");
}

std::string read_image_head(const std::string& path, std::size_t size) {
    check_name(path);
    std::error_code ec;
    if (!fs::exists(path, ec)) throw Error("cannot open image " + path + " (" + std::strerror(ENOENT) + ")");
    check_input_file(path); // before opening: a FIFO would block
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw Error("cannot open image " + path + " (" + std::strerror(errno) + ")");
    std::string head(size, '\0');
    head.resize(std::fread(head.data(), 1, size, f));
    std::fclose(f);
    return head;
}

std::string read_file(const std::string& path) {
    check_input_file(path);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open (" + std::strerror(errno) + ")");
    return guarded(path, [&] {
        std::ostringstream ss;
        ss << in.rdbuf();
        if (in.bad()) throw Error(path + ": read error");
        return std::move(ss).str();
    });
}

void write_file_atomic(const std::string& path, std::string_view bytes) {
    write_file_atomic(path, [&](const WriteBytes& write) { write(bytes); });
}

void write_file_atomic(const std::string& path, const std::function<void(const WriteBytes&)>& produce) {
    // One output staged and committed: a device, FIFO or descriptor is
    // written in place, anything else through a temporary and rename().
    StagedFiles files;
    files.stage(path, produce);
    files.commit();
}

bool same_file(const std::string& a, const std::string& b) {
    if (a.empty() || b.empty() || a == "-" || b == "-") return false;
    std::error_code ea, eb;
    // Both exist: the same inode (hard links, symlinks, "./x" vs "x").
    struct stat sa, sb;
    if (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    // Otherwise (an output not written yet): the same canonical path.
    fs::path ca = fs::weakly_canonical(a, ea), cb = fs::weakly_canonical(b, eb);
    return !ea && !eb && ca == cb;
}

} // namespace depthcull::io
