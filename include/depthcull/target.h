// depthcull: cost profiles as files and --target planning (issue 14), in
// the pipeline layer: io depends on no cost type. Everything here may do
// I/O and throws depthcull::io::Error with a one-line message naming the
// file and the place.
#pragma once

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
CostProfile load_profile(const std::string& path);
void save_profile(const std::string& path, const CostProfile& profile); // atomic
// --target NAME|FILE: a built-in name ("llvmpipe", "ipad1") or a profile file.
CostProfile resolve_target(const std::string& name_or_path);

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
