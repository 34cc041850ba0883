// The depthcull command line: one file per subcommand, each adding itself
// to the app. Errors are thrown as depthcull::Error (CliError is one) and
// printed by main() as one line. Exit status (README, "Exit status"): 0 success,
// 1 an error in the input or output, 2 a usage error.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "depthcull/analyze.h"
#include "depthcull/error.h"
#include "depthcull/io.h"
#include "depthcull/pipeline.h"
#include "depthcull/scene.h"
#include "pipeline/stopwatch.h"

namespace depthcull::cli {

// A command's own error (an option that does not fit the input): the
// library's one exception, so main() catches one type.
struct CliError : depthcull::Error {
    using depthcull::Error::Error;
};
// A command line that asks for nothing sensible: exit status 2, as CLI11's
// own usage errors.
struct UsageError : CliError {
    using CliError::CliError;
};

void add_analyze_command(CLI::App& app);
void add_optimize_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_import_command(CLI::App& app);
void add_atlas_command(CLI::App& app);
void add_report_command(CLI::App& app);
void add_calibrate_command(CLI::App& app);

// The command line as given (set by main), for reports.
extern std::string g_command_line;

// Wall time at the edge (src/pipeline/stopwatch.h, pipeline::optimize's).
using pipeline::Stopwatch;

// `path` empty or "-": stdout; otherwise written atomically.
void write_output(const std::string& path, const std::string& text);
// The same for output made in pieces (never held whole).
void write_output(const std::string& path, const std::function<void(const io::WriteBytes&)>& produce);

// The analysis options shared by analyze, atlas and the scene commands:
// --max-vertices, --filter, --opaque, --max-opaque, --min-coverage,
// --min-opaque-area, --no-split. Per image, --filter is options.filter.
void add_analysis_options(CLI::App& command, AnalyzeOptions& options);
// For scenes: the same, --filter into options.filter (set only when given,
// pipeline::settle decides who wins), the others into options.analyze.
void add_scene_analysis_options(CLI::App& command, pipeline::PrepareOptions& options);

// The element order and overlap test shared by optimize, render and bench:
// --graph, --sort.
void add_reconstruct_options(CLI::App& command, ReconstructOptions& options);

// An option taking one of a few names for an enum value. CLI11's
// CheckedTransformer over an enum map lists the choices as numbers in its
// error ("{fast->1,...}"); this one names them: "--opaque: 'bogus' is not
// one of fast, grow, paper".
template <class E>
CLI::Validator choice(std::vector<std::pair<std::string, E>> names) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n.first;
    auto check = [names, list](std::string& value) -> std::string {
        for (const auto& [name, e] : names)
            if (name == value) {
                value = std::to_string(static_cast<long long>(e));
                return {};
            }
        return "'" + value + "' is not one of " + list;
    };
    return CLI::Validator(check, "{" + list + "}");
}

// Rejects nan and infinities (which CLI::Range lets through).
CLI::Validator finite_number();

// CliError when an output names the same file as an input or as another
// output (io::same_file): `import m.tmx -o m.tmx` overwrote the map; or
// when an output is never written (a directory). See RunOutputs (outputs.h).
void check_distinct_files(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs);
// A scene's files: the scene, its images and the other files its load read
// (`documents`: external tilesets, templates, atlases; io::LoadOptions).
std::vector<std::string> scene_inputs(const std::string& scene_path, const Scene& scene, const std::vector<std::string>& documents);

// The analysis cache, one rule for every command: --cache DIR and
// --no-cache, and the directory they select ("" for none).
struct CacheChoice {
    std::string dir;
    bool off = false;
    std::string directory() const; // "" when off, else dir or pipeline::default_cache_dir()
};
void add_cache_options(CLI::App& command, CacheChoice& cache);

// --viewport x,y,w,h: the camera rectangle in world units (for Tiled maps
// and scenes alike); sets options.has_viewport. Also --strict and the
// warning / note lines map readers print.
void add_viewport_option(CLI::App& command, io::LoadOptions& options);


} // namespace depthcull::cli
