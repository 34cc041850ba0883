#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>

#include "cli.h"
#include "depthcull/io.h"
#include "depthcull/limits.h"
#include "depthcull/staged_files.h"
#include "outputs.h"

namespace depthcull::cli {

std::string g_command_line;

void write_output(const std::string& path, const std::string& text) {
    write_output(path, [&text](const io::WriteBytes& write) { write(text); });
}

void write_output(const std::string& path, const std::function<void(const io::WriteBytes&)>& produce) {
    // Staged like every output: stdout ("" or "-") too, so a failed write
    // to it (a full disk behind `> file`) is an error, not exit 0.
    io::StagedFiles files;
    files.stage(path, produce);
    files.commit();
}

CLI::Validator finite_number() {
    // CLI::Range lets "nan" through (every comparison with it is false).
    return CLI::Validator(
        [](std::string& value) -> std::string {
            char* end = nullptr;
            double v = std::strtod(value.c_str(), &end);
            return std::isfinite(v) ? std::string() : "'" + value + "' is not a finite number";
        },
        "FINITE");
}

void check_distinct_files(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs) {
    RunOutputs plan(inputs);
    for (const std::string& out : outputs) plan.add(out);
}

std::vector<std::string> scene_inputs(const std::string& scene_path, const Scene& scene, const std::vector<std::string>& documents) {
    std::vector<std::string> inputs{scene_path};
    for (const SceneImage& image : scene.images) inputs.push_back(image.path);
    inputs.insert(inputs.end(), documents.begin(), documents.end());
    return inputs;
}

namespace {

// --filter into `filter` (per image: analyze, atlas) or, for scenes, into
// `given` (set only when given: pipeline::settle lets it win over the
// scene's own filter).
void add_boundary_options(CLI::App& cmd, BoundaryOptions& o, Filter* filter, std::optional<Filter>* given) {
    cmd.add_option("--max-vertices", o.max_vertices, "Most vertices per boundary polygon (paper: MAX_BOUNDARY_VERTICES)")
        ->check(CLI::Range(kMinBoundaryVertices, 1000))
        ->capture_default_str();
    const char* help = "Texture filtering the polygons must be correct for (given: it wins over a scene's own)";
    CLI::Option* option = filter ? cmd.add_option("--filter", *filter, help)
                                 : cmd.add_option_function<Filter>("--filter", [given](const Filter& f) { *given = f; }, help);
    option->transform(choice<Filter>({{"nearest", Filter::nearest}, {"linear", Filter::linear}}))->default_str("nearest");
    cmd.add_flag("!--no-split", o.split_parts, "One boundary polygon per image, even for disjoint parts");
}

void add_opaque_options(CLI::App& cmd, AnalyzeOptions& o);

} // namespace

void add_analysis_options(CLI::App& cmd, AnalyzeOptions& o) {
    add_boundary_options(cmd, o.boundary, &o.filter, nullptr);
    add_opaque_options(cmd, o);
}

void add_scene_analysis_options(CLI::App& cmd, pipeline::PrepareOptions& o) {
    add_boundary_options(cmd, o.analyze.boundary, nullptr, &o.filter);
    add_opaque_options(cmd, o.analyze);
}

namespace {

void add_opaque_options(CLI::App& cmd, AnalyzeOptions& o) {
    cmd.add_option("--opaque", o.opaque.method, "Opaque polygon algorithm: fast (default: grown convex polygons, never below the paper), grow (the growth alone, "
                   "fastest) paper (paper 2.2, the reference) or cover (the opaque region in as many convex pieces as "
                   "pay, up to --max-opaque; docs/opaque.md)")
        ->transform(choice<OpaqueMethod>({{"fast", OpaqueMethod::fast},
                                          {"grow", OpaqueMethod::grow},
                                          {"paper", OpaqueMethod::paper},
                                          {"cover", OpaqueMethod::cover}}))
        ->default_str("fast");
    cmd.add_option("--max-opaque", o.opaque.max_polygons, "Most opaque polygons per image (paper: MAX_OPAQUE_POLYGONS; 0 disables)")
        ->check(CLI::Range(0, 64))
        ->capture_default_str();
    cmd.add_option("--min-coverage", o.opaque.min_coverage, "Stop adding opaque polygons at this fraction of opaque texels covered")
        ->check(finite_number())
        ->check(CLI::Range(0.0, 1.0))
        ->capture_default_str();
    cmd.add_option("--min-opaque-area", o.opaque.min_area,
                   "Skip an opaque polygon reaching fewer new opaque texels than this: those it touches grown by half "
                   "a texel, as the paper counts its quads (paper: MIN_OPAQUE_AREA)")
        ->check(CLI::Range(1, 1 << 30))
        ->capture_default_str();
}

} // namespace

void add_reconstruct_options(CLI::App& cmd, ReconstructOptions& o) {
    cmd.add_option("--graph", o.graph, "Element overlap test: polygons (default) or boxes (the paper's simple test)")
        ->transform(choice<GraphMode>({{"polygons", GraphMode::polygons}, {"boxes", GraphMode::boxes}}))
        ->default_str("polygons");
    cmd.add_option("--sort", o.sort, "Element order: batch (ours, default), paper (SortElements), none")
        ->transform(choice<SortMethod>({{"batch", SortMethod::batch}, {"paper", SortMethod::paper}, {"none", SortMethod::none}}))
        ->default_str("batch");
}

std::string CacheChoice::directory() const {
    if (off) return {};
    return dir.empty() ? pipeline::default_cache_dir() : dir;
}

void add_cache_options(CLI::App& cmd, CacheChoice& cache) {
    cmd.add_option("--cache", cache.dir,
                   "Analysis cache directory, shared by every command (default: $XDG_CACHE_HOME/depthcull/analysis or "
                   "~/.cache/depthcull/analysis)");
    cmd.add_flag("--no-cache", cache.off, "Analyze every image, read and write no cache");
}

void add_viewport_option(CLI::App& cmd, io::LoadOptions& options) {
    cmd.add_option_function<std::string>(
           "--viewport",
           [&options](const std::string& text) {
               double x, y;
               int w, h;
               char tail;
               // "nan,nan,64,64" scanned fine and crashed render: x and y
               // must be finite and within kMaxCoordinate.
               if (std::sscanf(text.c_str(), "%lf,%lf,%d,%d%c", &x, &y, &w, &h, &tail) != 4 || w <= 0 || h <= 0 ||
                   w > kMaxImageSide || h > kMaxImageSide || !(std::fabs(x) <= limits::kMaxCoordinate) ||
                   !(std::fabs(y) <= limits::kMaxCoordinate))
                   throw CLI::ValidationError("--viewport", "expected x,y,w,h with finite |x|, |y| <= 1e9 and 0 < w, h <= 16384, got '" +
                                                                text + "'");
               options.has_viewport = true;
               options.viewport = {x, y, w, h};
           },
           "Camera rectangle x,y,w,h in world units (default: the scene's viewport)")
        ->type_name("X,Y,W,H");
    // What a map reader approximates or leaves out: one line each on
    // stderr, or an error with --strict.
    options.warning = [](const std::string& line) { std::fprintf(stderr, "warning: %s\n", line.c_str()); };
    options.note = [](const std::string& line) { std::fprintf(stderr, "note: %s\n", line.c_str()); };
    cmd.add_flag("--strict", options.strict, "Refuse a map feature we approximate or leave out instead of warning");
}


} // namespace depthcull::cli
