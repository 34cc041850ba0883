// depthcull: how outputs are written (README, "Outputs"). Nothing a run
// writes may clobber what it must not: what an output path names decides
// how it is written, and a run's outputs are staged first and committed
// together, so a run that fails writes none of them.
#pragma once

#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "depthcull/io.h"

namespace depthcull::io {

// What an output path names:
//  - nothing or a regular file: `file`, written to a temporary beside it and
//    renamed over it (a reader never sees half a file);
//  - a symlink: followed (to its last target), which is then replaced as
//    above; the link stays a link;
//  - a character device or a FIFO (/dev/null, a named pipe): `in_place`,
//    opened and written, never replaced (run as root, a rename over
//    /dev/null would replace the system's);
//  - /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N, and "" or "-":
//    `descriptor`, this process's own descriptor N (a shell's `> file` or
//    `>> file` behind it is honoured, not replaced);
//  - a directory, a block device or a socket: refused (depthcull::Error).
struct OutputTarget {
    enum Kind { file, in_place, descriptor };
    Kind kind = file;
    std::string path;   // as given ("stdout" for "" and "-"), for messages
    std::string target; // file / in_place: the file written (a link's target)
    int fd = -1;        // descriptor
    bool is_fifo = false;
};
// Throws depthcull::Error naming `path`: a refused kind, a file name over NAME_MAX
// (255 bytes), a symlink loop, a descriptor not open.
OutputTarget resolve_output(const std::string& path);
// Whether two outputs may name one file: writing a character device
// (/dev/null) or a descriptor twice clobbers nothing.
bool output_may_repeat(const OutputTarget& target);

// A run's output files: each staged (written whole: to its temporary beside
// it, or for in-place outputs to an anonymous temporary file), then all
// committed at once (renamed, or copied into the device, FIFO or
// descriptor). What is not committed when this is destroyed is removed: a
// run that fails (an error, an exception) leaves none of its outputs and no
// temporaries. stage() may be called from several threads.
class StagedFiles {
public:
    StagedFiles() = default;
    StagedFiles(const StagedFiles&) = delete;
    StagedFiles& operator=(const StagedFiles&) = delete;
    ~StagedFiles();

    // The bytes `produce` hands its writer, in order, into `path`'s
    // temporary; if `produce` throws, that temporary is removed and the
    // error passes on. A failed write: Error "PATH: write failed (...)".
    void stage(const std::string& path, const std::function<void(const WriteBytes&)>& produce);
    void stage(const std::string& path, std::string_view bytes);
    // Copies into the streams (stdout, devices, FIFOs), then renames the
    // files, each in the order staged; Error on a failure (a stream that
    // fails leaves no file renamed).
    void commit();

private:
    struct Staged {
        OutputTarget target;
        std::string temp;             // file: the temporary beside the target
        std::FILE* spool = nullptr;   // in_place / descriptor: anonymous temporary
    };
    void discard(Staged& staged);
    std::mutex mutex_;
    std::vector<Staged> staged_;
    std::map<std::string, std::vector<std::string>> stale_; // per directory: dead writers' temporaries
};

// The name of the temporary that stands for `target` (a file's path) while
// it is written: ".NAME.tmp.<pid>.<n>" beside it, NAME cut so the whole
// fits NAME_MAX (255 bytes) even when NAME itself is 255 bytes long.
std::string temporary_name(const std::string& target, long pid, unsigned long long n);

} // namespace depthcull::io
