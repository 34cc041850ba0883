// Progress of long work on stderr: one line rewritten in place ("\r"),
// with done/total, rate and time left, only when stderr is a terminal and
// --quiet was not given, so logs and pipes get nothing.
#pragma once

#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

#include <CLI/CLI.hpp>

namespace depthcull::cli {

class Progress {
public:
    // `what`: "analyze", `unit`: "images".
    Progress(std::string what, std::string unit, std::size_t total, bool quiet);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    bool enabled() const { return enabled_; }
    // Thread-safe; redraws at most every 100 ms.
    void set(std::size_t done, std::size_t total);
    void add(std::size_t n = 1);
    // A new stage of the same work ("scene 2/5: drawing").
    void stage(const std::string& text);
    // Erases the line.
    void finish();

private:
    void draw_locked(bool force);

    bool enabled_ = false;
    std::string what_, unit_, stage_;
    std::size_t done_ = 0, total_ = 0;
    std::chrono::steady_clock::time_point start_, last_;
    std::size_t last_width_ = 0;
    std::mutex mutex_;
};

// Whether stderr is a terminal (progress and interactive hints).
bool stderr_is_terminal();
bool stdout_is_terminal();

// -q,--quiet: no progress, no summaries on stderr.
void add_quiet_flag(CLI::App& command, bool& quiet);

} // namespace depthcull::cli
