#include "testing/corpus.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;

namespace depthcull::test {

std::string corpus_dir() {
    if (const char* d = std::getenv("DEPTHCULL_CORPUS"); d && *d) return d;
    if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return std::string(d) + "/depthcull/corpus";
    const char* home = std::getenv("HOME");
    return std::string(home ? home : "/tmp") + "/.cache/depthcull/corpus";
}

std::string corpus_missing(const std::string& package) {
    fs::path dir = fs::path(corpus_dir()) / package;
    std::error_code ec;
    if (fs::is_directory(dir, ec)) return {};
    return "corpus package '" + package + "' not found under " + corpus_dir() + " (run scripts/fetch-corpus)";
}

std::vector<std::string> corpus_files(const std::string& package, const std::string& suffix) {
    std::vector<std::string> files;
    fs::path dir = fs::path(corpus_dir()) / package;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return files;
    for (auto it = fs::recursive_directory_iterator(dir, fs::directory_options::skip_permission_denied, ec);
         it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (ec) break;
        std::string p = it->path().string();
        if (it->is_regular_file(ec) && p.size() >= suffix.size() && p.compare(p.size() - suffix.size(), suffix.size(), suffix) == 0)
            files.push_back(p);
    }
    std::sort(files.begin(), files.end());
    return files;
}

std::string source_path(const std::string& relative) { return std::string(DEPTHCULL_SOURCE_DIR) + "/" + relative; }

} // namespace depthcull::test
