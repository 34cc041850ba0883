// depthcull analyze: per-image boundary and opaque polygons (paper 2.1,
// 2.2) as JSON, and the analyzer's summary.
#include <algorithm>
#include <cctype>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <regex>

#include <nlohmann/json.hpp>

#include "cli.h"
#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "depthcull/report.h"
#include "outputs.h"
#include "pipeline/parallel.h"
#include "progress.h"
#include "target_common.h"

namespace depthcull::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Input {
    std::string path;
    bool has_rect = false;
    Rect rect;
    int cell = -1; // IMAGE:grid=...: the cell's index, row-major
};

struct AnalyzeArgs {
    std::vector<std::string> inputs;
    std::string output;
    AnalyzeOptions options;
    bool summary = false;
    bool check = false;
    bool timing = true;
    unsigned threads = 0;
    std::string preview_dir;
    CacheChoice cache;
    std::string cache_dir; // resolved from `cache`
    bool quiet = false;
    bool strict = false;         // --strict: refuse what a decode assumed (io::report_warnings)
    std::string target;          // --target: the profile's name or file
    bool has_profile = false;
    CostProfile profile;         // resolved from target
};

// IMAGE:grid=W,H[,margin,spacing]: a sprite sheet or strip, every W x H
// cell its own frame, cut as Tiled cuts a tileset (cells start at `margin`,
// `spacing` apart; a partial cell at the right or bottom edge is none).
std::vector<Input> grid_inputs(const std::string& arg, const std::string& path, int w, int h, int margin, int spacing) {
    if (w <= 0 || h <= 0 || w > kMaxImageSide || h > kMaxImageSide || margin > kMaxImageSide || spacing > kMaxImageSide)
        throw CliError(arg + ": grid cell size must be 1.." + std::to_string(kMaxImageSide) + ", margin and spacing 0.." + std::to_string(kMaxImageSide));
    int width = 0, height = 0;
    io::image_size(path, &width, &height); // the header: the cells decode it (once, SharedDecodes)
    int columns = width - margin >= w ? (width - margin - w) / (w + spacing) + 1 : 0;
    int rows = height - margin >= h ? (height - margin - h) / (h + spacing) + 1 : 0;
    if (columns == 0 || rows == 0)
        throw CliError(arg + ": the " + std::to_string(width) + "x" + std::to_string(height) + " image holds no " +
                       std::to_string(w) + "x" + std::to_string(h) + " grid cell");
    if (std::size_t(columns) * std::size_t(rows) > limits::kMaxAtlasFrames)
        throw CliError(arg + ": the grid has " + std::to_string(std::int64_t(columns) * rows) + " cells, more than " +
                       std::to_string(limits::kMaxAtlasFrames) + " (kMaxAtlasFrames)");
    std::vector<Input> cells;
    for (int r = 0; r < rows; ++r)
        for (int c = 0; c < columns; ++c)
            cells.push_back({path, true, {margin + c * (w + spacing), margin + r * (h + spacing), w, h}, r * columns + c});
    return cells;
}

// IMAGE, IMAGE:x,y,w,h or IMAGE:grid=W,H[,margin,spacing]. Only a trailing
// ":int,int,int,int" is a rect, so paths with colons still work.
std::vector<Input> parse_input(const std::string& arg) {
    static const std::regex rect_suffix(R"(^(.*):(\d+),(\d+),(\d+),(\d+)$)");
    static const std::regex grid_suffix(R"(^(.*):grid=(\d+),(\d+)(?:,(\d+),(\d+))?$)");
    std::smatch m;
    Input in;
    if (std::regex_match(arg, m, grid_suffix)) {
        try {
            return grid_inputs(arg, m[1], std::stoi(m[2]), std::stoi(m[3]), m[4].matched ? std::stoi(m[4]) : 0,
                               m[5].matched ? std::stoi(m[5]) : 0);
        } catch (const std::out_of_range&) {
            throw CliError(arg + ": grid numbers out of range");
        }
    }
    if (std::regex_match(arg, m, rect_suffix)) {
        in.path = m[1];
        in.has_rect = true;
        try {
            in.rect = {std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4]), std::stoi(m[5])};
        } catch (const std::exception&) {
            throw CliError(arg + ": rectangle coordinates out of range");
        }
    } else {
        in.path = arg;
    }
    return {in};
}

std::vector<Input> expand_inputs(const std::vector<std::string>& args) {
    std::vector<Input> inputs;
    for (const auto& arg : args) {
        std::error_code ec;
        if (fs::is_directory(arg, ec)) {
            std::vector<std::string> found;
            for (auto it = fs::recursive_directory_iterator(arg, fs::directory_options::skip_permission_denied, ec);
                 !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
                std::string ext = it->path().extension().string();
                std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
                if ((ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".webp") && it->is_regular_file(ec)) found.push_back(it->path().string());
            }
            if (ec) throw CliError(arg + ": cannot list directory (" + ec.message() + ")");
            std::sort(found.begin(), found.end());
            for (auto& p : found) inputs.push_back({p, false, {}});
        } else {
            for (Input& in : parse_input(arg)) inputs.push_back(std::move(in));
        }
    }
    if (inputs.empty()) throw CliError("analyze: no PNG, JPEG or WebP images found in the given inputs");
    return inputs;
}

json polygons_json(const std::vector<Polygon>& polygons) {
    json out = json::array();
    for (const auto& p : polygons) {
        json poly = json::array();
        for (const Vec2& v : p) poly.push_back({v.x, v.y});
        out.push_back(std::move(poly));
    }
    return out;
}

struct Result {
    int width = 0, height = 0;
    ImageAnalysis analysis;
    std::int64_t uncontained = 0, violations = 0;
    bool cache_hit = false;
    int chosen_budget = -1;      // --target: the vertex budget chosen (0: the plain rect)
    double seconds = 0;          // wall time this run spent on the analysis (a cache read on a hit)
    std::vector<std::string> warnings; // what the decode assumed (a CMYK JPEG, an animated WebP)
};

// Preview file names: the image's stem, its rect when one was given, and
// -2, -3... for repeats (distinct_names: ignoring case, skipping names
// another input gives), so every input gets its own pair of files.
std::vector<std::string> preview_names(const std::vector<Input>& inputs) {
    std::vector<std::string> stems;
    for (const Input& in : inputs) {
        std::string name = fs::path(in.path).stem().string();
        if (in.has_rect)
            name += "_" + std::to_string(in.rect.x) + "_" + std::to_string(in.rect.y) + "_" + std::to_string(in.rect.w) + "_" +
                    std::to_string(in.rect.h);
        for (char& c : name)
            if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
        stems.push_back(name);
    }
    return distinct_names(stems, 4); // .png, .svg
}

// Each image file decoded once, by the first worker whose input needs it,
// and released after its last input: several inputs may cut one sheet (a
// grid's cells, rects), and a sheet of 2,080 cells was decoded 2,080 times
// (70 s against 0.9 s for the whole image). Inputs come in file order, so
// about one image per worker is held at a time.
class SharedDecodes {
public:
    explicit SharedDecodes(const std::vector<Input>& inputs) {
        for (const Input& in : inputs) ++slots_[in.path].left;
    }
    // The decoded image and its decode's warnings (a failed decode is
    // thrown to each input that asks).
    std::shared_ptr<const Image> get(const std::string& path, std::vector<std::string>* warnings) {
        Slot& slot = slots_.at(path);
        std::lock_guard<std::mutex> lock(slot.mutex);
        if (!slot.image) {
            slot.warnings.clear();
            slot.image = std::make_shared<const Image>(io::read_image(path, &slot.warnings));
        }
        warnings->insert(warnings->end(), slot.warnings.begin(), slot.warnings.end());
        return slot.image;
    }
    // An input of `path` is done: the last one releases the image.
    void done(const std::string& path) {
        Slot& slot = slots_.at(path);
        std::lock_guard<std::mutex> lock(slot.mutex);
        if (--slot.left == 0) slot.image.reset();
    }

private:
    struct Slot {
        std::mutex mutex;
        std::size_t left = 0;
        std::shared_ptr<const Image> image;
        std::vector<std::string> warnings;
    };
    std::map<std::string, Slot> slots_; // built before the workers start: only the slots change
};

// The input's image, decoded (or shared with the other inputs of its
// file), and the rect analysed in it (the whole image when none was given).
std::shared_ptr<const Image> read_input(const Input& in, const AnalyzeArgs& args, SharedDecodes& shared, std::vector<std::string>* warnings,
                                        Rect* rect_out) {
    // The analysis' memory is checked on the header, before the decode:
    // a 649-byte JPEG can say 16384^2.
    int header_w = 0, header_h = 0;
    io::image_size(in.path, &header_w, &header_h);
    const Rect header_rect = in.has_rect ? in.rect : Rect{0, 0, header_w, header_h};
    if (!header_rect.empty() && header_rect.x >= 0 && header_rect.y >= 0 && header_rect.x <= header_w - header_rect.w &&
        header_rect.y <= header_h - header_rect.h)
        pipeline::check_analysis_memory(in.path, header_rect, args.options);
    std::shared_ptr<const Image> image = shared.get(in.path, warnings);
    if (args.strict && !warnings->empty()) throw CliError(warnings->front() + " (--strict)");
    Rect rect = in.has_rect ? in.rect : image->view().bounds();
    if (rect.empty() || !image->view().contains(rect))
        throw CliError(in.path + ": rectangle " + std::to_string(rect.x) + "," + std::to_string(rect.y) + "," +
                       std::to_string(rect.w) + "," + std::to_string(rect.h) + " is outside the " + std::to_string(image->width) +
                       "x" + std::to_string(image->height) + " image");
    *rect_out = rect;
    return image;
}

// --target: the analysis the profile chooses, into r.analysis and
// r.chosen_budget.
void analyze_for_target(const Image& image, const Rect& rect, const std::string& path, const AnalyzeArgs& args, Result& r) {
    // As optimize --target plans each image (pipeline::plan_target): the
    // budgets 4, 6, 8 up to the cap, MIN_OPAQUE_AREA from the profile;
    // here the one that draws the image once at scale 1 the fastest,
    // or its plain rect.
    AnalyzeOptions o = args.options;
    o.opaque.min_area = min_opaque_area(args.profile);
    const int cap = std::max(kMinBoundaryVertices, o.boundary.max_vertices);
    std::vector<int> budgets;
    for (int b : {4, 6, 8})
        if (b < cap) budgets.push_back(b);
    budgets.push_back(cap);
    std::vector<ImageAnalysis> analyses;
    r.cache_hit = true;
    for (int b : budgets) {
        o.boundary.max_vertices = b;
        bool hit = false;
        analyses.push_back(pipeline::analyze_cached(image.view(), rect, o, args.cache_dir, &hit, path));
        r.cache_hit = r.cache_hit && hit;
    }
    ImageAnalysis plain = analyses.back();
    if (!plain.boundary.empty()) {
        const double x0 = rect.x, y0 = rect.y, x1 = double(rect.x) + rect.w, y1 = double(rect.y) + rect.h;
        plain.boundary = {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
        plain.stats.boundary_area = double(rect.w) * rect.h;
        plain.stats.boundary_vertices = 4;
    }
    std::vector<const ImageAnalysis*> candidates;
    for (const ImageAnalysis& a : analyses) candidates.push_back(&a);
    candidates.push_back(&plain);
    const std::size_t c = pipeline::choose_image_candidate(candidates, args.profile);
    r.analysis = *candidates[c];
    r.chosen_budget = c < budgets.size() ? budgets[c] : 0;
}

Result analyze_input(const Input& in, const AnalyzeArgs& args, const std::string& preview_base, RunOutputs& outputs, SharedDecodes& shared) {
    std::vector<std::string> warnings;
    Rect rect;
    const std::shared_ptr<const Image> decoded = read_input(in, args, shared, &warnings, &rect);
    const Image& image = *decoded;
    Result r;
    r.width = image.width;
    r.height = image.height;
    const Stopwatch stopwatch;
    if (!args.has_profile) r.analysis = pipeline::analyze_cached(image.view(), rect, args.options, args.cache_dir, &r.cache_hit, in.path);
    else analyze_for_target(image, rect, in.path, args, r);
    r.seconds = stopwatch.seconds();
    r.warnings = std::move(warnings);
    if (!preview_base.empty()) {
        report::PreviewOptions options;
        options.title = fs::path(in.path).filename().string();
        const report::Preview preview = report::make_preview(image.view(), rect, {&r.analysis}, options);
        outputs.stage(preview_base + ".png", io::encode_png(preview.png.view()));
        outputs.stage(preview_base + ".svg", preview.svg);
    }
    if (args.check) {
        r.uncontained = count_uncontained_texels(image.view(), rect, r.analysis.boundary, args.options.filter);
        r.violations = count_opaque_violations(image.view(), rect, r.analysis.opaque, args.options.filter);
    }
    return r;
}

json result_json(const Input& in, const Result& r, bool timing, const AnalyzeArgs& args) {
    const ImageStats& s = r.analysis.stats;
    const Rect& rect = r.analysis.rect;
    json stats = {{"nontransparent_texels", s.nontransparent_texels},
                  {"opaque_texels", s.opaque_texels},
                  {"boundary_area", s.boundary_area},
                  {"bbox_area", s.bbox_area},
                  {"excess_area_ratio", s.excess_area_ratio()},
                  {"boundary_polygons", r.analysis.boundary.size()},
                  {"boundary_vertices", s.boundary_vertices},
                  {"opaque_polygons", r.analysis.opaque.size()},
                  {"opaque_area", s.opaque_area},
                  {"opaque_covered_texels", s.opaque_covered_texels},
                  {"opaque_coverage", s.opaque_coverage},
                  {"seconds", timing ? r.seconds : 0.0}};
    json out = {{"path", in.path},
            {"rect", {rect.x, rect.y, rect.w, rect.h}},
            {"width", r.width},
            {"height", r.height},
            {"boundary", polygons_json(r.analysis.boundary)},
            {"opaque", polygons_json(r.analysis.opaque)},
            {"stats", std::move(stats)}};
    if (r.chosen_budget >= 0)
        out["target"] = {{"profile", args.profile.name},
                         {"max_vertices", r.chosen_budget},
                         {"rect", r.chosen_budget == 0},
                         {"min_opaque_area", min_opaque_area(args.profile)}};
    if (in.cell >= 0) out["cell"] = in.cell;
    return out;
}

std::string summary_text(const std::vector<Result>& results, double wall_seconds) {
    std::int64_t texels = 0, opaque = 0, covered = 0, vertices = 0, polygons = 0, opaque_polygons = 0;
    double boundary = 0, bbox = 0, seconds = 0;
    for (const auto& r : results) {
        const ImageStats& s = r.analysis.stats;
        texels += s.nontransparent_texels;
        opaque += s.opaque_texels;
        covered += s.opaque_covered_texels;
        boundary += s.boundary_area;
        bbox += s.bbox_area;
        vertices += s.boundary_vertices;
        polygons += std::int64_t(r.analysis.boundary.size());
        opaque_polygons += std::int64_t(r.analysis.opaque.size());
        seconds += r.seconds;
    }
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "images                %zu\n"
                  "non-transparent texels %" PRId64 "\n"
                  "bounding-box area     %.0f  (excess ratio %.4f)\n"
                  "boundary area         %.1f  (excess ratio %.4f; best 1.0)\n"
                  "boundary polygons     %" PRId64 "  vertices %" PRId64 "\n"
                  "opaque texels         %" PRId64 "\n"
                  "opaque polygons       %" PRId64 "  covering %" PRId64 " texels (coverage %.4f; best 1.0)\n"
                  "analysis time         %.3f s summed, %.3f s wall\n",
                  results.size(), texels, bbox, texels ? bbox / double(texels) : 0.0, boundary,
                  texels ? boundary / double(texels) : 0.0, polygons, vertices, opaque, opaque_polygons, covered,
                  opaque ? double(covered) / double(opaque) : 0.0, seconds, wall_seconds);
    return buf;
}

// Step 1: the inputs' paths, each a UTF-8 name (it goes into the JSON,
// which must be UTF-8).
std::vector<std::string> input_paths(const std::vector<Input>& inputs) {
    std::vector<std::string> paths;
    for (const Input& in : inputs) {
        if (!io::valid_utf8(in.path)) throw CliError(in.path + ": file name is not valid UTF-8 (JSON output needs it)");
        paths.push_back(in.path);
    }
    return paths;
}

// Step 2: each input's preview files (none without --preview), declared,
// and their directory made.
std::vector<std::string> declare_previews(const AnalyzeArgs& args, const std::vector<Input>& inputs, RunOutputs& outputs) {
    std::vector<std::string> previews(inputs.size());
    if (args.preview_dir.empty()) return previews;
    const std::vector<std::string> names = preview_names(inputs);
    for (std::size_t i = 0; i < inputs.size(); ++i) {
        previews[i] = (fs::path(args.preview_dir) / names[i]).string();
        outputs.add(previews[i] + ".png");
        outputs.add(previews[i] + ".svg");
    }
    std::error_code ec;
    fs::create_directories(args.preview_dir, ec);
    if (!fs::is_directory(args.preview_dir))
        throw CliError(args.preview_dir + ": cannot create the preview directory" + (ec ? " (" + ec.message() + ")" : ""));
    return previews;
}

// Step 3: every input analysed, on args.threads workers.
std::vector<Result> analyze_all(const AnalyzeArgs& args, const std::vector<Input>& inputs, const std::vector<std::string>& previews,
                                RunOutputs& outputs) {
    std::vector<Result> results(inputs.size());
    Progress progress("analyze", "images", inputs.size(), args.quiet);
    SharedDecodes shared(inputs);
    pipeline::parallel_for(inputs.size(), args.threads, [&](std::size_t i) {
        results[i] = analyze_input(inputs[i], args, previews[i], outputs, shared);
        shared.done(inputs[i].path);
        progress.add();
    });
    return results;
}

// Step 4: what the decodes assumed, in input order, each line once (the
// cells of one sheet share theirs), whatever the threads did first.
void print_warnings(const std::vector<Result>& results) {
    std::vector<std::string> warnings;
    for (const Result& r : results) warnings.insert(warnings.end(), r.warnings.begin(), r.warnings.end());
    io::LoadOptions report;
    report.warning = [](const std::string& line) { std::fprintf(stderr, "warning: %s\n", line.c_str()); };
    io::report_warnings(warnings, report);
}

// Step 5 (--check): the first input whose polygons fail stops the run;
// else one line says what passed.
void check_results(const AnalyzeArgs& args, const std::vector<Input>& inputs, const std::vector<Result>& results) {
    for (std::size_t i = 0; i < results.size(); ++i) {
        if (results[i].uncontained || results[i].violations)
            throw CliError(inputs[i].path + ": check failed: " + std::to_string(results[i].uncontained) +
                           " non-transparent texels outside the boundary, " + std::to_string(results[i].violations) +
                           " non-opaque texels touched by opaque polygons");
    }
    if (args.quiet) return;
    std::int64_t texels = 0, opaque_polygons = 0, boundary_polygons = 0;
    for (const Result& r : results) {
        texels += r.analysis.stats.nontransparent_texels;
        boundary_polygons += std::int64_t(r.analysis.boundary.size());
        opaque_polygons += std::int64_t(r.analysis.opaque.size());
    }
    const bool linear = args.options.filter == Filter::linear;
    std::fprintf(stderr,
                 "depthcull: check passed: %zu images: all %" PRId64 " non-transparent texels%s lie inside the %" PRId64
                 " boundary polygons, and the %" PRId64 " opaque polygons touch no texel that is not fully opaque%s\n",
                 results.size(), texels, linear ? " (grown by half a texel for linear filtering)" : "", boundary_polygons,
                 opaque_polygons, linear ? " (nor come within half a texel of one)" : "");
}

// Step 6: the JSON, one image per line: diffable, and still one JSON document.
std::string results_json(const AnalyzeArgs& args, const std::vector<Input>& inputs, const std::vector<Result>& results) {
    std::string text = "{\"images\": [\n";
    for (std::size_t i = 0; i < inputs.size(); ++i)
        text += " " + result_json(inputs[i], results[i], args.timing, args).dump() + (i + 1 < inputs.size() ? ",\n" : "\n");
    return text + "]}\n";
}

// Step 7 (--summary): the totals and the cache's share.
void print_summary(const std::vector<Result>& results, double wall) {
    std::string text = summary_text(results, wall);
    int hits = 0;
    for (const Result& r : results) hits += r.cache_hit;
    text += "from the cache        " + std::to_string(hits) + " of " + std::to_string(results.size()) + " images\n";
    std::fputs(text.c_str(), stdout);
}

void run_analyze(const AnalyzeArgs& args) {
    const Stopwatch stopwatch;
    std::vector<Input> inputs = expand_inputs(args.inputs);
    // Every output (the JSON, two previews per input) checked against every
    // input and every other output before the first is written; all are
    // committed together once every image is analyzed (`analyze . --preview
    // .` would have replaced the images with their previews).
    RunOutputs outputs(input_paths(inputs));
    outputs.add_inputs(target_inputs(args.target));
    const bool json_output = !args.summary || !args.output.empty();
    if (json_output) outputs.add(args.output.empty() ? "-" : args.output);
    const std::vector<std::string> previews = declare_previews(args, inputs, outputs);
    const std::vector<Result> results = analyze_all(args, inputs, previews, outputs);
    const double wall = stopwatch.seconds();
    print_warnings(results);
    if (args.check) check_results(args, inputs, results);
    if (json_output) outputs.stage(args.output.empty() ? "-" : args.output, results_json(args, inputs, results));
    outputs.commit();
    if (args.summary) print_summary(results, wall);
    if (!args.preview_dir.empty() && !args.quiet)
        std::fprintf(stderr, "depthcull: %zu previews (PNG and SVG) in %s\n", inputs.size(), args.preview_dir.c_str());
}

void set_cache(AnalyzeArgs& args) {
    args.cache_dir = args.cache.directory();
    if (!args.target.empty()) {
        args.profile = resolve_cli_target(args.target, args.quiet);
        args.has_profile = true;
    }
}

} // namespace

void add_analyze_command(CLI::App& app) {
    auto args = std::make_shared<AnalyzeArgs>();
    auto* cmd = app.add_subcommand("analyze", "Compute boundary and opaque polygons of images (paper 2.1, 2.2) as JSON");
    cmd->add_option("inputs", args->inputs, "IMAGE (PNG, JPEG, WebP), IMAGE:x,y,w,h (a sub-rectangle), IMAGE:grid=W,H[,margin,spacing] (every cell of a sprite sheet), or a directory of images")->required();
    cmd->add_option("-o,--output", args->output, "Write JSON here instead of stdout");
    add_analysis_options(*cmd, args->options);
    cmd->add_flag("--summary", args->summary, "Print totals over all inputs (JSON only with -o)");
    cmd->add_flag("--check", args->check, "Verify the guarantees exactly and fail on any violation");
    cmd->add_flag("!--no-timing", args->timing, "Write 0 for seconds, for byte-identical output across runs");
    cmd->add_option("-j,--threads", args->threads, "Worker threads (0: all cores)")->capture_default_str();
    cmd->add_option("--preview", args->preview_dir,
                    "Write a PNG and an SVG per image here: texels magnified on a checkerboard, boundary and opaque polygons, "
                    "triangles, figures")
        ->type_name("DIR");
    add_cache_options(*cmd, args->cache);
    cmd->add_flag("--strict", args->strict,
                  "Refuse an image we read by an assumption (a CMYK JPEG without its colour profile, an animated WebP's first frame) "
                  "instead of warning");
    add_target_option(*cmd, args->target);
    add_quiet_flag(*cmd, args->quiet);
    cmd->callback([args] {
        set_cache(*args);
        run_analyze(*args);
    });
}

} // namespace depthcull::cli
