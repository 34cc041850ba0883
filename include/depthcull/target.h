// depthcull: cost profiles as files and --target planning (issue 14).
// Everything here may do I/O and throws depthcull::io::Error with a
// one-line message naming the file and the place.
#pragma once

#include <deque>
#include <string>
#include <vector>

#include "depthcull/cost.h"
#include "depthcull/io.h"

namespace depthcull::io {

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

// What --target chose for a prepared scene: per element the analysis to
// reconstruct with (into `candidates` and `choice.storage`; keep the plan
// alive while they are used) and whether the opaque pass is drawn.
struct TargetPlan {
    CostProfile profile;
    std::vector<int> budgets;              // vertex budgets analyzed, ascending; the last is --max-vertices
    int min_opaque_area = 0;               // MIN_OPAQUE_AREA from the profile
    std::deque<ImageAnalysis> candidates;  // per distinct rect and budget
    TargetChoice choice;
    int analyzed = 0, cache_hits = 0;
    // Reconstruction options with the choice applied (opaque_polygons).
    ReconstructOptions reconstruct;
};

// Analyzes each distinct image rect of `prepared` at a few vertex budgets
// (4, 6, 8 up to options.analyze's cap) with the profile's MIN_OPAQUE_AREA
// (through the cache), then choose_for_target. Deterministic; never
// depends on options.threads.
TargetPlan plan_target(const PreparedScene& prepared, const PrepareOptions& options, const CostProfile& profile,
                       const ReconstructOptions& reconstruct);

// Per image (no scene): the candidate that minimizes the model's cost of
// drawing the image once at scale 1 with nothing behind it (`analyze
// --target`): boundary triangles, perimeter and fragments.
std::size_t choose_image_candidate(const std::vector<const ImageAnalysis*>& candidates, const CostProfile& profile);

} // namespace depthcull::io
