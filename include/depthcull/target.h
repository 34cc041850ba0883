// depthcull: cost profiles as files and --target planning (issue 14), in
// the pipeline layer: io depends on no cost type. Everything here may do
// I/O and throws depthcull::Error with a one-line message naming the
// file and the place.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "depthcull/cost.h"
#include "depthcull/pipeline.h"

namespace depthcull::pipeline {

// A profile is plain JSON (docs/cost-model.md):
// {"depthcull_profile": 1, "name": ..., "renderer": ..., "source": ...,
//  "frame_us": ..., "clear_color_ns_per_pixel": ..., ... every CostProfile term}
// Every term is required, finite and >= 0; unknown keys are refused.
CostProfile profile_from_json(const std::string& text, const std::string& name);
std::string profile_to_json(const CostProfile& profile);
CostProfile read_profile(const std::string& path);
void write_profile(const std::string& path, const CostProfile& profile); // atomic
// --target NAME|FILE: a built-in name ("llvmpipe", "ipad1") or a profile file.
CostProfile resolve_target(const std::string& name_or_path);

// ---- --target auto (issue 25): the profile of the GL renderer found.
// `renderer` is the renderer's description (GL_RENDERER, GL_VERSION and the
// EGL platform, render::GlHost::description()). In this order:
// 1. a built-in profile the string names (Mesa's llvmpipe -> "llvmpipe");
// 2. the profile cached for exactly that string in `cache_dir`
//    (profile_cache_path), when it loads and its "renderer" is the string;
// 3. calibrate()'s profile (depthcull calibrate's measurement), its
//    renderer set to the string and written to the cache atomically.
// A cache entry that does not load (a corrupt or hand-edited file) is
// measured again and replaced, with one line to `warning`: the cache is
// ours, as the analysis cache is. An empty cache_dir: nothing is cached.
// *how says which (for the commands' one line). Throws depthcull::Error when the
// cache cannot be written (naming the file), or what calibrate throws.
struct AutoProfile {
    CostProfile profile;
    std::string how; // "built-in", "cached in FILE", "calibrated, cached in FILE", "calibrated (not cached)"
};
AutoProfile auto_profile(const std::string& renderer, const std::string& cache_dir, const std::function<CostProfile()>& calibrate,
                         const std::function<void(const std::string&)>& warning = nullptr);
// The built-in profile a renderer description names (false: none).
bool builtin_profile_for_renderer(const std::string& renderer, CostProfile* out);
// $XDG_CACHE_HOME/depthcull/profiles, else ~/.cache/depthcull/profiles;
// empty when neither can be found.
std::string default_profile_cache_dir();
// The cache file of a renderer: <cache_dir>/<64-bit FNV-1a of the string, hex>.json.
std::string profile_cache_path(const std::string& cache_dir, const std::string& renderer);

// The paper's Table 2 as tests/data/paper-table2.tsv holds it.
std::vector<Table2Row> read_table2_tsv(const std::string& path);

// The one line the commands print about a plan (without a newline):
// "<path>: --target <name>: predicted ... ms ...".
std::string target_summary(const std::string& path, const TargetPlan& plan);

// Per image (no scene): the candidate that minimizes the model's cost of
// drawing the image once at scale 1 with nothing behind it (`analyze
// --target`): boundary triangles, perimeter and fragments.
std::size_t choose_image_candidate(const std::vector<const ImageAnalysis*>& candidates, const CostProfile& profile);

} // namespace depthcull::pipeline
