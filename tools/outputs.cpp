#include "outputs.h"

#include <cctype>
#include <set>

#include "cli.h"

namespace depthcull::cli {

void RunOutputs::add_inputs(const std::vector<std::string>& inputs) {
    inputs_.insert(inputs_.end(), inputs.begin(), inputs.end());
    for (std::size_t i = 0; i < outputs_.size(); ++i) check(i);
}

void RunOutputs::add(const std::string& path) {
    if (path.empty()) return;
    targets_.push_back(io::resolve_output(path));
    outputs_.push_back(path);
    check(outputs_.size() - 1);
}

void RunOutputs::check(std::size_t i) const {
    const std::string& out = outputs_[i];
    for (const std::string& in : inputs_)
        if (io::same_file(out, in)) throw CliError(out + ": refusing to overwrite an input (" + in + ") with an output");
    // /dev/null or stdout twice clobbers nothing; any other file twice
    // would keep only the last.
    if (io::output_may_repeat(targets_[i])) return;
    for (std::size_t j = 0; j < outputs_.size(); ++j)
        if (j != i && !io::output_may_repeat(targets_[j]) && io::same_file(out, outputs_[j]))
            throw CliError(out + ": two outputs name the same file (" + outputs_[j] + ")");
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
