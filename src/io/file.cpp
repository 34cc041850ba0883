#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <unistd.h>

#include "depthcull/io.h"

namespace depthcull::io {

namespace {
// Files larger than this are not images or scenes we accept.
constexpr std::uintmax_t kMaxFileBytes = std::uintmax_t(1) << 30;
} // namespace

std::string read_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) throw Error(path + ": is a directory, expected a file");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open (" + std::strerror(errno) + ")");
    auto size = std::filesystem::file_size(path, ec);
    if (!ec && size > kMaxFileBytes) throw Error(path + ": file is larger than 1 GiB");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) throw Error(path + ": read error");
    return std::move(ss).str();
}

void write_file_atomic(const std::string& path, std::string_view bytes) {
    namespace fs = std::filesystem;
    fs::path target(path);
    fs::path dir = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    // A unique name per process and call, so concurrent writers never share
    // a temporary file; rename() then replaces the target atomically.
    static thread_local std::mt19937_64 rng(std::random_device{}() ^ std::uint64_t(::getpid()));
    fs::path tmp = dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()) + "." + std::to_string(rng() % 1000000007));
    {
        std::FILE* f = std::fopen(tmp.c_str(), "wb");
        if (!f) throw Error(path + ": cannot write (" + std::strerror(errno) + ")");
        bool ok = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
        ok = (std::fflush(f) == 0) && ok;
        ok = (::fsync(::fileno(f)) == 0 || errno == EINVAL) && ok;
        ok = (std::fclose(f) == 0) && ok;
        if (!ok) {
            int e = errno;
            std::remove(tmp.c_str());
            throw Error(path + ": write failed (" + std::strerror(e) + ")");
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        int e = errno;
        std::remove(tmp.c_str());
        throw Error(path + ": cannot replace (" + std::strerror(e) + ")");
    }
}

} // namespace depthcull::io
