#include "outputs.h"

#include <cctype>
#include <filesystem>
#include <set>

#include <sys/stat.h>

#include "cli.h"

namespace depthcull::cli {

namespace fs = std::filesystem;

RunOutputs::FileKey RunOutputs::key_of(const std::string& path) {
    struct stat st;
    if (::stat(path.c_str(), &st) == 0) return "inode " + std::to_string(st.st_dev) + ":" + std::to_string(st.st_ino);
    std::error_code ec;
    const fs::path canonical = fs::weakly_canonical(path, ec);
    return "path " + (ec ? fs::path(path).lexically_normal() : canonical).string();
}

void RunOutputs::add_inputs(const std::vector<std::string>& inputs) {
    for (const std::string& in : inputs) {
        if (in.empty() || in == "-") continue;
        const FileKey key = key_of(in);
        const auto out = outputs_.find(key);
        if (out != outputs_.end()) throw CliError(out->second + ": refusing to overwrite an input (" + in + ") with an output");
        inputs_.emplace(key, in);
    }
}

void RunOutputs::add(const std::string& path) {
    if (path.empty()) return;
    const io::OutputTarget target = io::resolve_output(path);
    if (path == "-") return; // stdout: never an input's file by name
    const FileKey key = key_of(path);
    const auto in = inputs_.find(key);
    if (in != inputs_.end()) throw CliError(path + ": refusing to overwrite an input (" + in->second + ") with an output");
    // /dev/null or stdout twice clobbers nothing; any other file twice
    // would keep only the last.
    if (io::output_may_repeat(target)) return;
    const auto [out, added] = outputs_.emplace(key, path);
    if (!added) throw CliError(path + ": two outputs name the same file (" + out->second + ")");
}

namespace {

constexpr std::size_t kNameMax = 255;

// At most `bytes` bytes of `name`, never ending inside a UTF-8 sequence.
std::string cut(const std::string& name, std::size_t bytes) {
    if (name.size() <= bytes) return name;
    std::size_t n = bytes;
    while (n > 0 && (static_cast<unsigned char>(name[n]) & 0xC0) == 0x80) --n;
    return name.substr(0, n);
}

std::string folded(std::string name) {
    for (char& c : name) c = char(std::tolower(static_cast<unsigned char>(c)));
    return name;
}

} // namespace

std::vector<std::string> distinct_names(const std::vector<std::string>& stems, std::size_t extension_bytes) {
    const std::size_t room = kNameMax - extension_bytes;
    std::set<std::string> asked, used;
    for (const std::string& stem : stems) asked.insert(folded(cut(stem, room)));
    std::vector<std::string> names;
    for (const std::string& stem : stems) {
        std::string name = cut(stem, room);
        for (int n = 2; used.count(folded(name)); ++n) {
            const std::string suffix = "-" + std::to_string(n);
            const std::string candidate = cut(stem, room - suffix.size()) + suffix;
            if (!asked.count(folded(candidate))) name = candidate;
        }
        used.insert(folded(name));
        names.push_back(name);
    }
    return names;
}

} // namespace depthcull::cli
