#include <algorithm>
#include <cstdio>

#include "cli.h"
#include "depthcull/io.h"

namespace depthcull::cli {

void write_output(const std::string& path, const std::string& text) {
    if (path.empty() || path == "-") {
        std::fwrite(text.data(), 1, text.size(), stdout);
        std::fflush(stdout);
        return;
    }
    io::write_file_atomic(path, text);
}

void add_boundary_options(CLI::App& cmd, BoundaryOptions& o) {
    cmd.add_option("--max-vertices", o.max_vertices, "Most vertices per boundary polygon (paper: MAX_BOUNDARY_VERTICES)")
        ->check(CLI::Range(kMinBoundaryVertices, 1000))
        ->capture_default_str();
    cmd.add_option("--filter", o.filter, "Texture filtering the polygons must be correct for")
        ->transform(choice<Filter>({{"nearest", Filter::nearest}, {"linear", Filter::linear}}))
        ->default_str("nearest");
    cmd.add_flag("!--no-split", o.split_parts, "One boundary polygon per image, even for disjoint parts");
}

void add_analysis_options(CLI::App& cmd, AnalyzeOptions& o) {
    add_boundary_options(cmd, o.boundary);
    cmd.add_option("--opaque", o.opaque.method, "Opaque polygon algorithm: fast (default: grown convex polygons, never below the paper), grow (the growth alone, "
                   "fastest) or paper (paper 2.2, the reference)")
        ->transform(choice<OpaqueMethod>({
            {"fast", OpaqueMethod::fast}, {"grow", OpaqueMethod::grow}, {"paper", OpaqueMethod::paper}}))
        ->default_str("fast");
    cmd.add_option("--max-opaque", o.opaque.max_polygons, "Most opaque polygons per image (paper: MAX_OPAQUE_POLYGONS; 0 disables)")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    cmd.add_option("--min-coverage", o.opaque.min_coverage, "Stop adding opaque polygons at this fraction of opaque texels covered")
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd.add_option("--min-opaque-area", o.opaque.min_area,
                   "Skip an opaque polygon reaching fewer new opaque texels than this: those it touches grown by half "
                   "a texel, as the paper counts its quads (paper: MIN_OPAQUE_AREA)")
        ->check(CLI::Range(1, 1 << 30))
        ->capture_default_str();
}

void add_reconstruct_options(CLI::App& cmd, ReconstructOptions& o) {
    cmd.add_option("--graph", o.graph, "Element overlap test: polygons (default) or boxes (the paper's simple test)")
        ->transform(choice<GraphMode>({{"polygons", GraphMode::polygons}, {"boxes", GraphMode::boxes}}))
        ->default_str("polygons");
    cmd.add_option("--sort", o.sort, "Element order: batch (ours, default), paper (SortElements), none")
        ->transform(choice<SortMethod>({{"batch", SortMethod::batch}, {"paper", SortMethod::paper}, {"none", SortMethod::none}}))
        ->default_str("batch");
}

void add_viewport_option(CLI::App& cmd, io::LoadOptions& options) {
    cmd.add_option_function<std::string>(
           "--viewport",
           [&options](const std::string& text) {
               double x, y;
               int w, h;
               char tail;
               if (std::sscanf(text.c_str(), "%lf,%lf,%d,%d%c", &x, &y, &w, &h, &tail) != 4 || w <= 0 || h <= 0 ||
                   w > kMaxImageSide || h > kMaxImageSide)
                   throw CLI::ValidationError("--viewport", "expected x,y,w,h with 0 < w, h <= 16384, got '" + text + "'");
               options.has_viewport = true;
               options.viewport = {x, y, w, h};
           },
           "Camera rectangle x,y,w,h in world units (default: the scene's viewport)")
        ->type_name("X,Y,W,H");
}


} // namespace depthcull::cli
