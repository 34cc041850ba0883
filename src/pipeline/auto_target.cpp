// --target auto (issue 25): the profile of the GL renderer found, built in
// or calibrated once and cached with its renderer string.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "depthcull/target.h"
#include "pipeline/cache.h"

namespace depthcull::pipeline {

bool builtin_profile_for_renderer(const std::string& renderer, CostProfile* out) {
    // Mesa's CPU rasterizer names itself "llvmpipe (LLVM ...)"; the built-in
    // profile was fitted on it (one thread, as bench and calibrate pin).
    if (renderer.rfind("llvmpipe", 0) == 0) return builtin_profile("llvmpipe", out);
    return false;
}

std::string default_profile_cache_dir() { return user_cache_dir("profiles"); }

std::string profile_cache_path(const std::string& cache_dir, const std::string& renderer) {
    std::uint64_t h = 14695981039346656037ull; // FNV-1a: stable across builds and platforms, unlike std::hash
    for (unsigned char c : renderer) h = (h ^ c) * 1099511628211ull;
    char name[32];
    std::snprintf(name, sizeof name, "%016llx.json", (unsigned long long)h);
    return (std::filesystem::path(cache_dir) / name).string();
}

AutoProfile auto_profile(const std::string& renderer, const std::string& cache_dir, const std::function<CostProfile()>& calibrate,
                         const std::function<void(const std::string&)>& warning) {
    AutoProfile out;
    if (builtin_profile_for_renderer(renderer, &out.profile)) {
        out.how = "built-in";
        return out;
    }
    const std::string path = cache_dir.empty() ? std::string() : profile_cache_path(cache_dir, renderer);
    std::error_code ec;
    if (!path.empty() && std::filesystem::exists(path, ec)) {
        std::string problem;
        try {
            CostProfile cached = read_profile(path);
            // Another renderer's entry (a hash collision, a copied file) is measured again too.
            if (cached.renderer == renderer) {
                out.profile = std::move(cached);
                out.how = "cached in " + path;
                return out;
            }
            problem = path + ": measured on '" + cached.renderer + "', not this renderer";
        } catch (const depthcull::Error& e) {
            problem = e.what();
        }
        if (warning) warning("--target auto: " + problem + "; calibrating again");
    }
    out.profile = calibrate();
    out.profile.renderer = renderer;
    if (out.profile.name.empty()) out.profile.name = "calibrated";
    if (path.empty()) {
        out.how = "calibrated (not cached: no cache directory)";
        return out;
    }
    std::filesystem::create_directories(cache_dir, ec);
    if (ec) throw depthcull::Error(cache_dir + ": cannot create the profile cache: " + ec.message());
    write_profile(path, out.profile);
    out.how = "calibrated, cached in " + path;
    return out;
}

} // namespace depthcull::pipeline
