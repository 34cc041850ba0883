// Only in builds with the renderer (DEPTHCULL_BUILD_RENDER).
#ifdef DEPTHCULL_HAVE_RENDER
#include "render_common.h"
#include "target_common.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>

namespace depthcull::cli {

void add_render_input_options(CLI::App& cmd, RenderInput& in) {
    add_cache_options(cmd, in.cache);
    add_reconstruct_options(cmd, in.reconstruct);
    cmd.add_flag("!--no-opaque", in.opaque, "Optimized without the opaque pass: boundary polygons only");
    add_viewport_option(cmd, in.prepare.load);
    add_scene_analysis_options(cmd, in.prepare);
    add_target_option(cmd, in.target);
    add_target_stage_options(cmd, in.prepare);
    cmd.add_option("-j,--threads", in.prepare.threads, "Worker threads for the analysis (0: all cores)")->capture_default_str();
    cmd.add_option("--gl", in.platform,
                   "EGL platform: auto (a GPU device if any, else Mesa surfaceless), surfaceless, device")
        ->transform(choice<render::GlPlatform>({{"auto", render::GlPlatform::automatic},
                                                {"surfaceless", render::GlPlatform::surfaceless},
                                                {"device", render::GlPlatform::device}}))
        ->default_str("auto");
}

pipeline::OptimizeOptions optimize_options(const RenderInput& in) {
    pipeline::OptimizeOptions o;
    o.prepare = in.prepare;
    o.prepare.cache_dir = in.cache.directory();
    o.reconstruct = in.reconstruct;
    o.reconstruct.opaque_polygons = in.opaque;
    o.target = in.target;
    o.reconstruct_meshes = false; // each mode's meshes are built for drawing
    return o;
}

pipeline::OptimizeResult optimize_for_render(const std::string& path, const RenderInput& in, bool quiet,
                                             const std::function<void(const char*)>& stage) {
    pipeline::OptimizeOptions o = optimize_options(in);
    if (!in.target.empty()) o.profile = resolve_cli_target(in.target, quiet); // --target auto finds the GL renderer here
    o.stage = stage;
    pipeline::OptimizeResult result = pipeline::optimize(path, o);
    if (result.plan && !quiet) std::fprintf(stderr, "depthcull: %s\n", pipeline::target_summary(path, *result.plan).c_str());
    return result;
}

std::vector<ImageView> image_views(const pipeline::PreparedScene& prepared) {
    return prepared.views();
}

namespace {
// What the CLI adds to render::NoContext's one line.
CliError no_context(const render::NoContext& e) {
    return CliError(std::string(e.what()) + " (headless rendering needs Mesa's EGL: apt-get install libegl-mesa0 libgl1-mesa-dri)");
}
} // namespace

std::unique_ptr<render::GlRenderer> open_renderer(const RenderInput& in) {
    try {
        return render::GlRenderer::create({in.platform});
    } catch (const render::NoContext& e) {
        throw no_context(e);
    }
}

std::unique_ptr<render::GlHost> open_host(render::GlPlatform platform) {
    try {
        return render::GlHost::create({platform}, render::GlApi::desktop);
    } catch (const render::NoContext& e) {
        throw no_context(e);
    }
}

const char* pin_lp_threads(int lp_threads) {
    if (lp_threads >= 0) setenv("LP_NUM_THREADS", std::to_string(lp_threads).c_str(), 1);
    else if (!std::getenv("LP_NUM_THREADS")) setenv("LP_NUM_THREADS", "1", 1);
    return std::getenv("LP_NUM_THREADS");
}

double covered_share(const OverdrawMap& ideal) {
    if (ideal.counts.empty()) return 0;
    std::size_t covered = 0;
    for (std::uint32_t c : ideal.counts) covered += c > 0;
    return double(covered) / double(ideal.counts.size());
}

void check_frame_fits(const std::string& path, const pipeline::PreparedScene& prepared, const RenderInput& input) {
    const Viewport& frame = prepared.scene.viewport;
    if (std::int64_t(frame.width) * frame.height > limits::kMaxFramePixels)
        throw CliError(path + ": the " + std::to_string(frame.width) + "x" + std::to_string(frame.height) + " frame has " +
                       std::to_string(std::int64_t(frame.width) * frame.height) + " pixels, more than " +
                       std::to_string(limits::kMaxFramePixels) + " (8192x8192, kMaxFramePixels): give a smaller --viewport");
    if (input.prepare.load.has_viewport || prepared.scene.elements.empty()) return;
    const Viewport& vp = prepared.scene.viewport;
    if (vp.width < kMaxImageSide && vp.height < kMaxImageSide) return;
    double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
    for (const Element& e : prepared.scene.elements)
        for (Vec2 c : {Vec2{0, 0}, Vec2{double(e.rect.w), 0}, Vec2{0, double(e.rect.h)}, Vec2{double(e.rect.w), double(e.rect.h)}}) {
            const Vec2 s = apply(e.transform, c);
            x0 = std::min(x0, s.x), y0 = std::min(y0, s.y), x1 = std::max(x1, s.x), y1 = std::max(y1, s.y);
        }
    const double w = std::ceil(x1) - std::floor(x0), h = std::ceil(y1) - std::floor(y0);
    if (w <= vp.width && h <= vp.height) return;
    char buf[160];
    std::snprintf(buf, sizeof buf, "the scene draws %.0fx%.0f px, more than the %dx%d frame it gets (at most %d px per side, kMaxImageSide)", w, h,
                  vp.width, vp.height, kMaxImageSide);
    throw CliError(path + ": " + buf + ": give --viewport x,y,w,h (or a \"viewport\" in the scene) to draw a part of it");
}

std::vector<std::pair<std::string, std::string>> report_options(const RenderInput& in, int frames, int warmup, const char* shader) {
    const AnalyzeOptions& a = in.prepare.analyze;
    const char* lp = std::getenv("LP_NUM_THREADS");
    auto str = [](double v) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%g", v);
        return std::string(buf);
    };
    std::vector<std::pair<std::string, std::string>> o{
        {"shader", shader},
        {"frames", std::to_string(frames) + " timed (median), " + std::to_string(warmup) + " warm-up, glFinish each"},
        {"LP_NUM_THREADS", lp ? lp : "(unset)"},
        {"filter", in.prepare.filter ? (*in.prepare.filter == Filter::linear ? "linear" : "nearest") : "the scene's"},
        {"max vertices", std::to_string(a.boundary.max_vertices)},
        {"split disjoint parts", a.boundary.split_parts ? "yes" : "no"},
        {"opaque method", a.opaque.method == OpaqueMethod::fast   ? "fast"
                          : a.opaque.method == OpaqueMethod::grow ? "grow"
                          : a.opaque.method == OpaqueMethod::cover ? "cover"
                                                                  : "paper"},
        {"max opaque polygons", std::to_string(a.opaque.max_polygons)},
        {"min coverage", str(a.opaque.min_coverage)},
        {"min opaque area", std::to_string(a.opaque.min_area)},
        {"opaque pass", in.opaque ? "yes" : "no (--no-opaque)"},
        {"graph", in.reconstruct.graph == GraphMode::polygons ? "polygons" : "boxes"},
        {"sort", in.reconstruct.sort == SortMethod::batch ? "batch" : in.reconstruct.sort == SortMethod::paper ? "paper" : "none"},
        {"cache", in.cache.off ? "off" : in.cache.directory()},
    };
    if (!in.target.empty()) {
        o.push_back({"target", in.target});
        o.push_back({"clip hidden parts", in.prepare.clip_hidden ? "where it pays" : "no (--no-clip-hidden)"});
        o.push_back({"merge opaque tiles", in.prepare.merge_opaque ? "yes" : "no (--no-merge-opaque)"});
        o.push_back({"opaque pieces (cover plan)", in.prepare.cover_plan ? "where faster" : "no (--no-cover-plan)"});
        o.push_back({"no depth buffer", in.prepare.depthless ? "where faster" : "no (--no-depthless)"});
    }
    if (in.prepare.load.has_viewport) {
        const Viewport& v = in.prepare.load.viewport;
        o.push_back({"viewport", str(v.x) + "," + str(v.y) + "," + std::to_string(v.width) + "," + std::to_string(v.height)});
    }
    return o;
}

namespace {

// Table 2's rows as measured: by the runtime renderer (rt) or the
// instrumented one (m).
void add_measured_rows(report::SceneReport& r, const render::RuntimeMeasurement* rt, const render::SceneMeasurement* m) {
    const double pixels = double(r.width) * double(r.height);
    if (rt) {
        r.ideal_overdraw = rt->ideal_overdraw;
        for (const render::RuntimeModeMeasurement& mm : rt->modes) {
            r.rows.push_back({render::mode_name(mm.mode), mm.draw_calls, mm.triangles, pixels > 0 ? double(mm.fragments_shaded) / pixels : 0,
                              mm.wall_ms, mm.cpu_ms, mm.diff.pixels_differ});
            if (mm.mode == render::Mode::overpaint) r.overpaint = mm.frame;
            if (mm.mode == render::Mode::optimized) r.optimized = mm.frame;
        }
    } else if (m) {
        r.ideal_overdraw = m->ideal_overdraw;
        for (const render::ModeMeasurement& mm : m->modes) {
            r.rows.push_back({render::mode_name(mm.mode), mm.counts.draw_calls, mm.counts.triangles, mm.overdraw, mm.ms_median, -1,
                              mm.diff.pixels_differ});
            if (mm.mode == render::Mode::overpaint) r.overpaint = mm.frame;
            if (mm.mode == render::Mode::optimized) r.optimized = mm.frame;
        }
    }
}

// Heatmaps by the CPU analyzers (they match GL_SAMPLES_PASSED exactly).
void add_heatmaps(report::SceneReport& r, const pipeline::OptimizeResult& result, const std::vector<ImageView>& views) {
    const pipeline::PreparedScene& prepared = result.prepared;
    const Scene& scene = prepared.scene;
    OverdrawMap ideal;
    const double od_ideal = ideal_overdraw(scene, views, &ideal).overdraw();
    r.covered = covered_share(ideal);
    for (render::Mode mode : {render::Mode::overpaint, render::Mode::optimized}) {
        SceneMeshes meshes;
        if (render::build_meshes(mode, scene, prepared.analysis, result.reconstruct, &meshes) != ReconstructStatus::ok)
            continue;
        OverdrawMap map;
        const double od = analyze_overdraw(meshes, &map).overdraw();
        r.heatmaps.push_back({render::mode_name(mode), map.width, map.height, std::move(map.counts), od});
    }
    r.heatmaps.push_back({"ideal", ideal.width, ideal.height, std::move(ideal.counts), od_ideal});
}

// One row of the images table: the analysis k, of scene image `image`.
report::ImageRow image_row(const pipeline::PreparedScene& prepared, std::size_t k, int image, std::int64_t uses,
                           const std::vector<ImageView>& views) {
    const ImageAnalysis& a = prepared.analysis.images[k];
    const SceneImage& si = prepared.scene.images[std::size_t(image)];
    report::ImageRow row;
    row.name = (si.id.empty() ? si.path : si.id);
    if (a.rect.x != 0 || a.rect.y != 0 || a.rect.w != si.width || a.rect.h != si.height)
        row.name += " [" + std::to_string(a.rect.x) + "," + std::to_string(a.rect.y) + "," + std::to_string(a.rect.w) + "," +
                    std::to_string(a.rect.h) + "]";
    row.rect = a.rect;
    const report::PreviewFigures f = report::preview_figures({&a});
    row.vertices = f.boundary_vertices;
    row.excess_area_ratio = f.excess_area_ratio();
    row.opaque_coverage = f.opaque_coverage();
    row.opaque_polygons = f.opaque_polygons;
    row.triangles = f.triangles;
    row.uses = uses;
    report::PreviewOptions options;
    options.size = 160;
    options.title = std::filesystem::path(si.path).filename().string();
    report::Preview p = report::make_preview(views[std::size_t(image)], a.rect, {&a}, options);
    row.preview = std::move(p.png);
    return row;
}

// Per image: uses by the elements, most used first (ties in first-use order).
void add_image_rows(report::SceneReport& r, const pipeline::PreparedScene& prepared, const std::vector<ImageView>& views) {
    const Scene& scene = prepared.scene;
    std::vector<std::int64_t> uses(prepared.analysis.images.size(), 0);
    std::vector<int> image_of(prepared.analysis.images.size(), -1);
    for (std::size_t e = 0; e < scene.elements.size() && e < prepared.analysis.of_element.size(); ++e) {
        const std::size_t k = prepared.analysis.of_element[e];
        if (k >= uses.size()) continue;
        ++uses[k];
        if (image_of[k] < 0) image_of[k] = scene.elements[e].image;
    }
    std::vector<std::size_t> order(uses.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return uses[a] > uses[b]; });
    constexpr std::size_t kMaxRows = 100;
    for (std::size_t n = 0; n < order.size() && n < kMaxRows; ++n) {
        const std::size_t k = order[n];
        if (image_of[k] < 0) continue;
        r.images_table.push_back(image_row(prepared, k, image_of[k], uses[k], views));
    }
    r.images_not_shown = order.size() > kMaxRows ? order.size() - kMaxRows : 0;
}

} // namespace

report::SceneReport scene_report(const std::string& path, const pipeline::OptimizeResult& result, const render::RuntimeMeasurement* rt,
                                 const render::SceneMeasurement* m) {
    const pipeline::PreparedScene& prepared = result.prepared;
    report::SceneReport r;
    const Scene& scene = prepared.scene;
    r.path = path;
    r.width = scene.viewport.width;
    r.height = scene.viewport.height;
    r.elements = scene.elements.size();
    r.images = prepared.analysis.images.size();
    add_measured_rows(r, rt, m);
    const std::vector<ImageView> views = image_views(prepared);
    add_heatmaps(r, result, views);
    add_image_rows(r, prepared, views);
    char buf[160];
    std::snprintf(buf, sizeof buf, "%d images analyzed, %d from the analysis cache", prepared.analyzed, prepared.cache_hits);
    r.analysis = buf;
    return r;
}

} // namespace depthcull::cli
#endif
