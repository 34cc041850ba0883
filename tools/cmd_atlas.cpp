// depthcull atlas SHEET.json -o OUT.json: a TexturePacker atlas written back
// with our boundary polygons in TexturePacker's polygon fields (vertices,
// verticesUV, triangles), for engines that draw polygon sprites. Frames are
// analyzed in parallel through the analysis cache optimize uses.
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <map>

#include "cli.h"
#include "depthcull/report.h"
#include "progress.h"

namespace depthcull::cli {

namespace {

namespace fs = std::filesystem;

struct AtlasArgs {
    std::string input;
    std::string output;
    AnalyzeOptions analyze;
    std::string preview_dir;
    CacheChoice cache;
    std::string godot_dir;
    bool quiet = false;
    bool strict = false;
    unsigned threads = 0;
};

std::string safe_name(std::string name) {
    for (char& c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.')) c = '_';
    return name;
}

// The page with every frame's polygons, and one preview per frame in
// DIR/frames/ (frame names made file-safe, numbered to stay distinct).
void write_previews(const AtlasArgs& args, const pipeline::AtlasAnalysis& a, bool quiet) {
    std::error_code ec;
    const fs::path dir(args.preview_dir), frames_dir = dir / "frames";
    fs::create_directories(frames_dir, ec);
    if (!fs::is_directory(frames_dir))
        throw CliError(args.preview_dir + ": cannot create the preview directory" + (ec ? " (" + ec.message() + ")" : ""));
    for (std::size_t k = 0; k < a.atlas.pages.size(); ++k) {
        std::vector<const ImageAnalysis*> all;
        for (std::size_t i = 0; i < a.frames.size(); ++i)
            if (std::size_t(a.atlas.frames[i].page) == k) all.push_back(&a.frames[i]);
        report::PreviewOptions page_options;
        page_options.title = fs::path(a.atlas.pages[k].image_path).filename().string();
        page_options.size = 1024;
        const std::string page_base = (dir / safe_name(fs::path(a.atlas.pages[k].image_path).stem().string())).string();
        const report::Preview page = report::make_preview(a.pages[k].view(), a.pages[k].view().bounds(), all, page_options);
        io::save_png(page_base + ".png", page.png.view());
        io::write_file_atomic(page_base + ".svg", page.svg);
    }
    Progress progress("atlas", "previews", a.frames.size(), quiet);
    pipeline::parallel_for(a.frames.size(), args.threads, [&](std::size_t i) {
        report::PreviewOptions options;
        options.title = a.atlas.frames[i].name;
        char number[16];
        std::snprintf(number, sizeof number, "%04zu_", i);
        const std::string base = (frames_dir / (number + safe_name(fs::path(a.atlas.frames[i].name).stem().string()))).string();
        const report::Preview p =
            report::make_preview(a.pages[std::size_t(a.atlas.frames[i].page)].view(), a.atlas.frames[i].frame, {&a.frames[i]}, options);
        io::save_png(base + ".png", p.png.view());
        io::write_file_atomic(base + ".svg", p.svg);
        progress.add();
    });
}

// DIR/<frame>.tscn per frame (names made file-safe, numbered to stay
// distinct), the page named relative to DIR.
void write_godot(const AtlasArgs& args, const pipeline::AtlasAnalysis& a) {
    std::error_code ec;
    const fs::path dir(args.godot_dir);
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir)) throw CliError(args.godot_dir + ": cannot create the Godot directory" + (ec ? " (" + ec.message() + ")" : ""));
    std::map<std::string, int> seen;
    for (std::size_t i = 0; i < a.frames.size(); ++i) {
        const io::AtlasFrame& frame = a.atlas.frames[i];
        std::string stem = safe_name(fs::path(frame.name).replace_extension().string());
        const int n = ++seen[stem];
        if (n > 1) stem += "-" + std::to_string(n);
        fs::path page = fs::absolute(a.atlas.pages[std::size_t(frame.page)].image_path, ec);
        std::string texture = fs::relative(page, fs::absolute(dir, ec), ec).generic_string();
        if (texture.empty()) texture = page.generic_string();
        io::write_file_atomic((dir / (stem + ".tscn")).string(), io::godot_polygon_scene(frame, a.frames[i].boundary, texture));
    }
}

void run_atlas(AtlasArgs& args) {
    std::vector<std::string> inputs{args.input};
    for (const io::AtlasPage& page : io::load_texturepacker(args.input).pages) inputs.push_back(page.image_path);
    check_distinct_files(inputs, {args.output});
    pipeline::AtlasPolygonOptions options;
    // A .plist output is cocos2d-x's format 3 with polygons, whatever the input.
    options.plist = args.output.size() > 6 && args.output.compare(args.output.size() - 6, 6, ".plist") == 0;
    options.analyze = args.analyze;
    options.cache_dir = args.cache.directory();
    options.threads = args.threads;
    options.strict = args.strict;
    options.warning = [](const std::string& line) { std::fprintf(stderr, "warning: %s\n", line.c_str()); };
    io::AtlasPolygonStats stats;
    pipeline::AtlasAnalysis analysis;
    std::string text;
    {
        Progress progress("atlas", "frames", 0, args.quiet);
        options.progress = [&progress](std::size_t done, std::size_t total) { progress.set(done, total); };
        text = pipeline::atlas_with_polygons(args.input, options, &stats, &analysis);
    }
    write_output(args.output, text);
    if (!args.preview_dir.empty()) write_previews(args, analysis, args.quiet);
    if (!args.godot_dir.empty()) write_godot(args, analysis);
    if (stats.rectangle_frames > 0)
        std::fprintf(stderr, "warning: %s: %d frames written as their rectangle (cocos2d-x plist vertices are integers; rounding their polygon would cut texels)\n",
                     args.input.c_str(), stats.rectangle_frames);
    if (args.quiet) return;
    // The analyzer's figure: area the engine fills, polygons vs whole frames.
    std::fprintf(stderr, "%s: %d frames, %lld vertices, %lld triangles, polygon area %.0f of %.0f frame texels (%.1f%%)\n",
                 args.input.c_str(), stats.frames, static_cast<long long>(stats.vertices), static_cast<long long>(stats.triangles),
                 stats.polygon_area, stats.frame_area, stats.frame_area > 0 ? 100.0 * stats.polygon_area / stats.frame_area : 0.0);
    if (!options.cache_dir.empty())
        std::fprintf(stderr, "%s: %d of %d frames from the analysis cache\n", args.input.c_str(), analysis.cache_hits, stats.frames);
    if (!args.preview_dir.empty())
        std::fprintf(stderr, "%s: previews (PNG and SVG) of the page and %zu frames in %s\n", args.input.c_str(), analysis.frames.size(),
                     args.preview_dir.c_str());
}

} // namespace

void add_atlas_command(CLI::App& app) {
    auto args = std::make_shared<AtlasArgs>();
    auto* cmd = app.add_subcommand("atlas", "Add boundary polygons to a TexturePacker JSON atlas (vertices, verticesUV, triangles)");
    cmd->add_option("atlas", args->input, "TexturePacker JSON (hash, array or multipack) or cocos2d-x .plist")->required();
    cmd->add_option("-o,--output", args->output,
                    "Atlas to write (default: stdout), in the input's form; a .plist name writes a cocos2d-x format 3 plist with polygons");
    add_analysis_options(*cmd, args->analyze);
    cmd->add_option("--preview", args->preview_dir,
                    "Write PNG and SVG previews here: the page with every frame's polygons, and each frame in frames/")
        ->type_name("DIR");
    cmd->add_option("--godot", args->godot_dir,
                    "Write a Godot scene per frame here (FRAME.tscn: a Polygon2D with texture, polygon, uv and polygons from our boundary polygons)")
        ->type_name("DIR");
    add_cache_options(*cmd, args->cache);
    cmd->add_flag("--strict", args->strict,
                  "Refuse what we read by an assumption (a page whose size differs from the atlas' meta.size, a CMYK JPEG, ...) "
                  "instead of warning");
    cmd->add_option("-j,--threads", args->threads, "Worker threads (0: all cores); output never depends on it")->capture_default_str();
    add_quiet_flag(*cmd, args->quiet);
    cmd->callback([args] { run_atlas(*args); });
}

} // namespace depthcull::cli
