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
#include "io/formats.h"

namespace depthcull::io {

namespace fs = std::filesystem;

namespace {

// Temporary files are named NAME.tmp.<pid>.<n> (hidden: ".NAME"), so a
// writer can tell which ones belong to a process that is gone.
std::string temp_prefix(const fs::path& target) { return "." + target.filename().string() + ".tmp."; }

bool process_gone(long pid) { return pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH; }

// Removes the temporaries a killed writer (kill -9, power loss) left
// beside `target`: those whose pid names no running process.
void remove_stale_temps(const fs::path& dir, const fs::path& target) {
    const std::string prefix = temp_prefix(target);
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        std::string name = it->path().filename().string();
        if (name.compare(0, prefix.size(), prefix) != 0) continue;
        char* tail = nullptr;
        long pid = std::strtol(name.c_str() + prefix.size(), &tail, 10);
        if (tail && *tail == '.' && process_gone(pid)) fs::remove(it->path(), ec), ec.clear();
    }
}

} // namespace

void check_input_file(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) != 0) throw Error(path + ": cannot open (" + std::strerror(errno) + ")");
    if (S_ISDIR(st.st_mode)) throw Error(path + ": is a directory, expected a file");
    // /dev/zero, a FIFO or a socket would be read without end (or block).
    if (!S_ISREG(st.st_mode)) throw Error(path + ": not a regular file (devices, FIFOs and sockets are not read)");
    if (std::uint64_t(st.st_size) > limits::kMaxFileBytes)
        throw Error(path + ": file is larger than 1 GiB (kMaxFileBytes)");
}

std::string read_image_head(const std::string& path, std::size_t size) {
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
    fs::path target(path);
    fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    remove_stale_temps(dir, target);
    // A unique name per process and call, so concurrent writers never share
    // a temporary file; rename() then replaces the target atomically.
    static std::atomic<std::uint64_t> counter{0};
    const fs::path tmp = dir / (temp_prefix(target) + std::to_string(::getpid()) + "." + std::to_string(counter++));
    std::FILE* f = std::fopen(tmp.c_str(), "wb");
    if (!f) throw Error(path + ": cannot write (" + std::strerror(errno) + ")");
    // The first failure's errno, kept until the end: a full disk fails
    // every later fwrite too, and the producer's own error wins over both.
    int error = 0;
    const WriteBytes write = [&](std::string_view bytes) {
        if (!error && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) error = errno ? errno : EIO;
    };
    try {
        produce(write);
    } catch (...) {
        std::fclose(f);
        std::remove(tmp.c_str());
        throw;
    }
    if (!error && std::fflush(f) != 0) error = errno;
    if (!error && ::fsync(::fileno(f)) != 0 && errno != EINVAL) error = errno;
    if (std::fclose(f) != 0 && !error) error = errno;
    if (error) {
        std::remove(tmp.c_str());
        throw Error(path + ": write failed (" + std::strerror(error) + ")");
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        int e = errno;
        std::remove(tmp.c_str());
        throw Error(path + ": cannot replace (" + std::strerror(e) + ")");
    }
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
