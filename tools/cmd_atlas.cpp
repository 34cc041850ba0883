// depthcull atlas SHEET.json -o OUT.json: a TexturePacker atlas written back
// with our boundary polygons in TexturePacker's polygon fields (vertices,
// verticesUV, triangles), for engines that draw polygon sprites. Frames are
// analyzed in parallel through the analysis cache optimize uses.
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "cli.h"
#include "depthcull/report.h"
#include "outputs.h"
#include "pipeline/parallel.h"
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

// The files --preview and --godot write, named before any is written:
// DIR/<page>.png/.svg (the page with every frame's polygons), one pair per
// frame in DIR/frames/ (numbered: distinct whatever the names), and
// GODOT/<frame>.tscn; names made file-safe, distinct (distinct_names: two
// multipack pages both named sheet.png, frames a.png, a.jpg and a-2) and
// cut to 255 bytes.
struct AtlasFiles {
    std::vector<std::string> pages, frames, godot; // pages / frames: without the extension
};

AtlasFiles atlas_files(const AtlasArgs& args, const pipeline::AtlasAnalysis& a) {
    AtlasFiles files;
    std::vector<std::string> stems;
    if (!args.preview_dir.empty()) {
        const fs::path dir(args.preview_dir), frames_dir = dir / "frames";
        for (const io::AtlasPage& page : a.atlas.pages) stems.push_back(safe_name(fs::path(page.image_path).stem().string()));
        for (const std::string& name : distinct_names(stems, 4)) files.pages.push_back((dir / name).string());
        stems.clear();
        for (std::size_t i = 0; i < a.atlas.frames.size(); ++i) {
            char number[24];
            std::snprintf(number, sizeof number, "%04zu_", i);
            stems.push_back(number + safe_name(fs::path(a.atlas.frames[i].name).stem().string()));
        }
        for (const std::string& name : distinct_names(stems, 4)) files.frames.push_back((frames_dir / name).string());
    }
    if (!args.godot_dir.empty()) {
        stems.clear();
        for (const io::AtlasFrame& frame : a.atlas.frames) stems.push_back(safe_name(fs::path(frame.name).replace_extension().string()));
        for (const std::string& name : distinct_names(stems, 5)) files.godot.push_back((fs::path(args.godot_dir) / (name + ".tscn")).string());
    }
    return files;
}

void make_directory(const fs::path& dir, const std::string& what) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!fs::is_directory(dir)) throw CliError(dir.string() + ": cannot create the " + what + " directory" + (ec ? " (" + ec.message() + ")" : ""));
}

void write_previews(const AtlasArgs& args, const pipeline::AtlasAnalysis& a, const AtlasFiles& files, RunOutputs& outputs, bool quiet) {
    make_directory(fs::path(args.preview_dir) / "frames", "preview");
    for (std::size_t k = 0; k < a.atlas.pages.size(); ++k) {
        std::vector<const ImageAnalysis*> all;
        for (std::size_t i = 0; i < a.frames.size(); ++i)
            if (std::size_t(a.atlas.frames[i].page) == k) all.push_back(&a.frames[i]);
        report::PreviewOptions page_options;
        page_options.title = fs::path(a.atlas.pages[k].image_path).filename().string();
        page_options.size = 1024;
        const report::Preview page = report::make_preview(a.pages[k].view(), a.pages[k].view().bounds(), all, page_options);
        outputs.stage(files.pages[k] + ".png", io::encode_png(page.png.view()));
        outputs.stage(files.pages[k] + ".svg", page.svg);
    }
    Progress progress("atlas", "previews", a.frames.size(), quiet);
    pipeline::parallel_for(a.frames.size(), args.threads, [&](std::size_t i) {
        report::PreviewOptions options;
        options.title = a.atlas.frames[i].name;
        const report::Preview p =
            report::make_preview(a.pages[std::size_t(a.atlas.frames[i].page)].view(), a.atlas.frames[i].frame, {&a.frames[i]}, options);
        outputs.stage(files.frames[i] + ".png", io::encode_png(p.png.view()));
        outputs.stage(files.frames[i] + ".svg", p.svg);
        progress.add();
    });
}

// GODOT/<frame>.tscn per frame, the page named relative to GODOT.
void write_godot(const AtlasArgs& args, const pipeline::AtlasAnalysis& a, const AtlasFiles& files, RunOutputs& outputs) {
    std::error_code ec;
    const fs::path dir(args.godot_dir);
    make_directory(dir, "Godot");
    for (std::size_t i = 0; i < a.frames.size(); ++i) {
        const io::AtlasFrame& frame = a.atlas.frames[i];
        fs::path page = fs::absolute(a.atlas.pages[std::size_t(frame.page)].image_path, ec);
        std::string texture = fs::relative(page, fs::absolute(dir, ec), ec).generic_string();
        if (texture.empty()) texture = page.generic_string();
        outputs.stage(files.godot[i], io::godot_polygon_scene(frame, a.frames[i].boundary, texture));
    }
}

void run_atlas(AtlasArgs& args) {
    std::vector<std::string> inputs{args.input};
    for (const io::AtlasPage& page : io::read_atlas(args.input).pages) inputs.push_back(page.image_path);
    // Every output checked against every input and every other output
    // before the first is written, all committed together at the end:
    // `atlas --preview .` would have replaced the page with its preview.
    RunOutputs outputs(inputs);
    outputs.add(args.output.empty() ? "-" : args.output);
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
    std::vector<std::string> pages;
    for (const io::AtlasPage& page : analysis.atlas.pages) pages.push_back(page.image_path);
    outputs.add_inputs(pages);
    const AtlasFiles files = atlas_files(args, analysis);
    for (const std::vector<std::string>* bases : {&files.pages, &files.frames})
        for (const std::string& base : *bases) {
            outputs.add(base + ".png");
            outputs.add(base + ".svg");
        }
    for (const std::string& path : files.godot) outputs.add(path);
    outputs.stage(args.output.empty() ? "-" : args.output, text);
    if (!args.preview_dir.empty()) write_previews(args, analysis, files, outputs, args.quiet);
    if (!args.godot_dir.empty()) write_godot(args, analysis, files, outputs);
    outputs.commit();
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
