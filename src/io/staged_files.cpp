// How outputs are written (depthcull/staged_files.h): the kind of file an
// output path names, and staging a run's outputs so they are committed
// together or not at all.
#include "depthcull/staged_files.h"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <atomic>
#include <filesystem>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace depthcull::io {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kNameMax = 255; // NAME_MAX on Linux and the BSDs
// ".tmp." + a pid (at most 10 digits) + "." + a counter (at most 20) and
// the leading ".": what a temporary's name adds to the target's.
constexpr std::size_t kTempSuffixBytes = 1 + 5 + 10 + 1 + 20;

// The start of every temporary's name for `name` (a file name).
std::string temp_prefix(const std::string& name) {
    return "." + name.substr(0, kNameMax - kTempSuffixBytes) + ".tmp.";
}

bool process_gone(long pid) { return pid > 0 && ::kill(pid_t(pid), 0) != 0 && errno == ESRCH; }

// The temporaries a killed writer (kill -9, power loss) left in `dir`:
// ".NAME.tmp.<pid>.<n>" whose pid names no running process. Listed once
// per directory and run, then removed as each NAME is written (a scan per
// file made writing 20,000 Godot scenes into one directory quadratic).
std::vector<std::string> stale_temps(const fs::path& dir) {
    std::vector<std::string> stale;
    std::error_code ec;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        const std::size_t tmp = name.rfind(".tmp.");
        if (name.empty() || name[0] != '.' || tmp == std::string::npos || tmp == 0) continue;
        char* tail = nullptr;
        const long pid = std::strtol(name.c_str() + tmp + 5, &tail, 10);
        if (tail && *tail == '.' && process_gone(pid)) stale.push_back(name);
    }
    return stale;
}

// "/dev/stdout", "/dev/fd/3", "/proc/self/fd/3", "/proc/<our pid>/fd/3":
// the descriptor, else -1. Such a path is a link into /proc whose target
// ("pipe:[123]", a tty, a file opened by the shell) cannot be replaced by
// name without losing what the shell set up.
int descriptor_of(const std::string& path) {
    if (path == "/dev/stdout") return 1;
    if (path == "/dev/stderr") return 2;
    for (const std::string& prefix : {std::string("/dev/fd/"), std::string("/proc/self/fd/"),
                                     "/proc/" + std::to_string(::getpid()) + "/fd/"}) {
        if (path.compare(0, prefix.size(), prefix) != 0 || path.size() == prefix.size() || path.size() > prefix.size() + 9) continue;
        const std::string digits = path.substr(prefix.size());
        if (digits.find_first_not_of("0123456789") != std::string::npos) continue;
        return std::stoi(digits);
    }
    return -1;
}

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw Error(path + ": " + what); }

// Writes all of `bytes` to `fd`, through EINTR and short writes.
bool write_all(int fd, const char* bytes, std::size_t size) {
    while (size > 0) {
        const ssize_t n = ::write(fd, bytes, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            if (n == 0) errno = EIO;
            return false;
        }
        bytes += n;
        size -= std::size_t(n);
    }
    return true;
}

// Copies the spooled bytes into `fd`; 0 or the errno of the failure.
int copy_spool(std::FILE* spool, int fd) {
    std::rewind(spool);
    char buffer[1 << 16];
    for (;;) {
        const std::size_t n = std::fread(buffer, 1, sizeof buffer, spool);
        if (n > 0 && !write_all(fd, buffer, n)) return errno ? errno : EIO;
        if (n < sizeof buffer) return std::ferror(spool) ? EIO : 0;
    }
}

} // namespace

std::string temporary_name(const std::string& target, long pid, unsigned long long n) {
    const fs::path path(target);
    return (path.parent_path() / (temp_prefix(path.filename().string()) + std::to_string(pid) + "." + std::to_string(n))).string();
}

OutputTarget resolve_output(const std::string& path) {
    OutputTarget out;
    out.path = path.empty() || path == "-" ? "stdout" : path;
    if (path.empty() || path == "-") {
        out.kind = OutputTarget::descriptor;
        out.fd = STDOUT_FILENO;
        return out;
    }
    std::string current = path;
    for (int links = 0;; ++links) {
        const int fd = descriptor_of(current);
        if (fd >= 0) {
            if (::fcntl(fd, F_GETFL) == -1) fail(path, "cannot write (descriptor " + std::to_string(fd) + " is not open)");
            out.kind = OutputTarget::descriptor;
            out.fd = fd;
            return out;
        }
        const fs::path p(current);
        if (p.filename().string().size() > kNameMax)
            fail(path, "cannot write (file name longer than " + std::to_string(kNameMax) + " bytes)");
        struct stat st;
        if (::lstat(current.c_str(), &st) != 0) {
            if (errno != ENOENT) fail(path, std::string("cannot write (") + std::strerror(errno) + ")");
            out.kind = OutputTarget::file; // a new file (a dangling link's target is made, as a shell's > does)
            out.target = current;
            return out;
        }
        if (S_ISLNK(st.st_mode)) {
            if (links >= 40) fail(path, std::string("cannot write (") + std::strerror(ELOOP) + ")");
            std::error_code ec;
            const fs::path to = fs::read_symlink(p, ec);
            if (ec) fail(path, "cannot write (" + ec.message() + ")");
            current = (to.is_absolute() ? to : p.parent_path() / to).string();
            continue;
        }
        out.target = current;
        if (S_ISREG(st.st_mode)) {
            out.kind = OutputTarget::file;
        } else if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) {
            out.kind = OutputTarget::in_place;
            out.is_fifo = S_ISFIFO(st.st_mode);
        } else if (S_ISDIR(st.st_mode)) {
            fail(path, "is a directory, expected a file to write");
        } else {
            fail(path, "cannot write: not a regular file, character device or FIFO (block devices and sockets are not written)");
        }
        return out;
    }
}

bool output_may_repeat(const OutputTarget& target) {
    return target.kind == OutputTarget::descriptor || (target.kind == OutputTarget::in_place && !target.is_fifo);
}

StagedFiles::~StagedFiles() {
    for (Staged& s : staged_) discard(s);
}

void StagedFiles::discard(Staged& s) {
    if (!s.temp.empty()) std::remove(s.temp.c_str());
    s.temp.clear();
    if (s.spool) std::fclose(s.spool);
    s.spool = nullptr;
}

void StagedFiles::stage(const std::string& path, std::string_view bytes) {
    stage(path, [&](const WriteBytes& write) { write(bytes); });
}

void StagedFiles::stage(const std::string& path, const std::function<void(const WriteBytes&)>& produce) {
    Staged s;
    s.target = resolve_output(path);
    std::FILE* f = nullptr;
    if (s.target.kind == OutputTarget::file) {
        const fs::path target(s.target.target);
        const fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
        std::vector<std::string> remove;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            auto found = stale_.find(dir.string());
            if (found == stale_.end()) found = stale_.emplace(dir.string(), stale_temps(dir)).first;
            // Only this target's: another file's may be a writer elsewhere.
            const std::string prefix = temp_prefix(target.filename().string());
            for (const std::string& name : found->second)
                if (name.compare(0, prefix.size(), prefix) == 0 && std::strtol(name.c_str() + prefix.size(), nullptr, 10) > 0) remove.push_back(name);
        }
        std::error_code ec;
        for (const std::string& name : remove) fs::remove(dir / name, ec);
        // A unique name per process and call, so concurrent writers never
        // share a temporary; rename() then replaces the target atomically.
        static std::atomic<unsigned long long> counter{0};
        s.temp = temporary_name(s.target.target, long(::getpid()), counter++);
        const int fd = ::open(s.temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 || !(f = ::fdopen(fd, "wb"))) {
            const int e = errno;
            if (fd >= 0) ::close(fd), std::remove(s.temp.c_str());
            fail(s.target.path, std::string("cannot write (") + std::strerror(e) + ")");
        }
    } else {
        // Held in an anonymous file (gone when closed, whatever happens)
        // until commit: a device or pipe cannot be taken back.
        f = s.spool = std::tmpfile();
        if (!f) fail(s.target.path, std::string("cannot write (no temporary file: ") + std::strerror(errno) + ")");
    }
    // The first failure's errno, kept until the end: a full disk fails
    // every later fwrite too, and the producer's own error wins over both.
    int error = 0;
    const WriteBytes write = [&](std::string_view bytes) {
        if (!error && std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size()) error = errno ? errno : EIO;
    };
    try {
        produce(write);
    } catch (...) {
        if (!s.spool) std::fclose(f);
        discard(s);
        throw;
    }
    if (!error && std::fflush(f) != 0) error = errno;
    if (!s.spool) {
        if (!error && ::fsync(::fileno(f)) != 0 && errno != EINVAL) error = errno;
        if (std::fclose(f) != 0 && !error) error = errno;
    }
    if (error) {
        discard(s);
        fail(s.target.path, std::string("write failed (") + std::strerror(error) + ")");
    }
    std::lock_guard<std::mutex> lock(mutex_);
    staged_.push_back(std::move(s));
}

void StagedFiles::commit() {
    std::lock_guard<std::mutex> lock(mutex_);
    // Streams first (stdout, devices, FIFOs), then the renames: a write
    // that fails (stdout on a full disk or a closed pipe) then leaves no
    // file renamed into place, where renaming first left the run's files
    // behind a run that failed. A rename rarely fails once its temporary
    // is written beside it.
    for (Staged& s : staged_) {
        const OutputTarget& t = s.target;
        if (t.kind == OutputTarget::file) continue;
        int fd = t.fd;
        if (t.kind == OutputTarget::in_place) {
            // No O_CREAT, no O_TRUNC: a device or FIFO is written as it is.
            fd = ::open(t.target.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
            if (fd < 0) fail(t.path, std::string("cannot write (") + std::strerror(errno) + ")");
        } else if (fd == STDOUT_FILENO) {
            std::fflush(stdout); // what the command printed before stays before
        }
        const int error = copy_spool(s.spool, fd);
        if (t.kind == OutputTarget::in_place) ::close(fd);
        std::fclose(s.spool);
        s.spool = nullptr;
        if (error) fail(t.path, std::string("write failed (") + std::strerror(error) + ")");
    }
    for (Staged& s : staged_) {
        const OutputTarget& t = s.target;
        if (t.kind != OutputTarget::file) continue;
        if (std::rename(s.temp.c_str(), t.target.c_str()) != 0) fail(t.path, std::string("cannot replace (") + std::strerror(errno) + ")");
        s.temp.clear();
    }
    staged_.clear();
}

} // namespace depthcull::io
