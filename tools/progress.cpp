#include "progress.h"

#include <cstdio>
#include <unistd.h>

namespace depthcull::cli {

bool stderr_is_terminal() { return ::isatty(STDERR_FILENO) == 1; }
bool stdout_is_terminal() { return ::isatty(STDOUT_FILENO) == 1; }

void add_quiet_flag(CLI::App& command, bool& quiet) {
    command.add_flag("-q,--quiet", quiet, "Print no progress and no summary on stderr (errors still are)");
}

Progress::Progress(std::string what, std::string unit, std::size_t total, bool quiet)
    : enabled_(!quiet && stderr_is_terminal()), what_(std::move(what)), unit_(std::move(unit)), total_(total),
      start_(std::chrono::steady_clock::now()), last_(start_) {
    if (enabled_) {
        std::lock_guard lock(mutex_);
        draw_locked(true);
    }
}

Progress::~Progress() { finish(); }

void Progress::set(std::size_t done, std::size_t total) {
    if (!enabled_) return;
    std::lock_guard lock(mutex_);
    done_ = done;
    total_ = total;
    draw_locked(false);
}

void Progress::add(std::size_t n) {
    if (!enabled_) return;
    std::lock_guard lock(mutex_);
    done_ += n;
    draw_locked(false);
}

void Progress::stage(const std::string& text) {
    if (!enabled_) return;
    std::lock_guard lock(mutex_);
    stage_ = text;
    draw_locked(true);
}

void Progress::draw_locked(bool force) {
    const auto now = std::chrono::steady_clock::now();
    if (!force && done_ < total_ && now - last_ < std::chrono::milliseconds(100)) return;
    last_ = now;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed > 0 ? double(done_) / elapsed : 0;
    char line[512];
    int n = std::snprintf(line, sizeof line, "%s: %s%s%zu/%zu %s", what_.c_str(), stage_.c_str(), stage_.empty() ? "" : ": ", done_,
                          total_, unit_.c_str());
    if (done_ > 0 && elapsed > 0.2 && n > 0 && std::size_t(n) < sizeof line) {
        const double left = rate > 0 && total_ > done_ ? double(total_ - done_) / rate : 0;
        n += std::snprintf(line + n, sizeof line - std::size_t(n), ", %.1f/s, %d:%02d left", rate, int(left) / 60, int(left) % 60);
    }
    const std::size_t width = std::string(line).size();
    // Pad over a longer previous line instead of relying on terminal codes.
    std::fprintf(stderr, "\r%s%*s", line, int(last_width_ > width ? last_width_ - width : 0), "");
    std::fflush(stderr);
    last_width_ = width;
}

void Progress::finish() {
    if (!enabled_) return;
    std::lock_guard lock(mutex_);
    if (last_width_ > 0) std::fprintf(stderr, "\r%*s\r", int(last_width_), "");
    std::fflush(stderr);
    last_width_ = 0;
    enabled_ = false;
}

} // namespace depthcull::cli
