// A run's outputs, planned before the first byte is written (README,
// "Outputs"): every output is checked against every input and every other
// output, then all are staged and committed together, so a run that fails
// writes none of them, and no output ever replaces an input.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "depthcull/staged_files.h"

namespace depthcull::cli {

class RunOutputs {
public:
    explicit RunOutputs(const std::vector<std::string>& inputs = {}) { add_inputs(inputs); }
    // More inputs (a scene's images, known once it is loaded): the outputs
    // declared so far are checked against them.
    void add_inputs(const std::vector<std::string>& inputs);
    // Declares an output ("-": stdout; "": none asked, ignored). CliError
    // when it names an input or another output (io::same_file), or names
    // what is never written (a directory: io::resolve_output).
    void add(const std::string& path);
    void stage(const std::string& path, const std::function<void(const io::WriteBytes&)>& produce) { files_.stage(path, produce); }
    void stage(const std::string& path, std::string_view bytes) { files_.stage(path, bytes); }
    void commit() { files_.commit(); }

private:
    // Which file a path names, as io::same_file decides it (the inode when
    // it exists, else the canonical path), computed once per path: an
    // atlas of 100,000 frames has 200,000 previews, far too many to compare
    // pair by pair.
    using FileKey = std::string;
    static FileKey key_of(const std::string& path);
    std::map<FileKey, std::string> inputs_, outputs_;
    io::StagedFiles files_;
};

// File names for outputs a run makes up (previews, Godot scenes), one per
// wanted stem, all in one directory: the stems cut so that stem + the
// longest of `extensions` fits 255 bytes (NAME_MAX), and made distinct
// ignoring case (a case-insensitive file system would merge "A" and "a"):
// a repeat gets -2, -3, ..., skipping every name some other entry asks for
// itself (frames "a.png", "a.jpg" and "a-2" give a, a-3 and a-2).
std::vector<std::string> distinct_names(const std::vector<std::string>& stems, std::size_t extension_bytes);

} // namespace depthcull::cli
