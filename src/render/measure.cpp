// Paper 3, Table 2: one scene drawn unoptimized, as meshes only, and fully
// optimized, with draw calls, triangles, overdraw and time per frame; plus
// what the paper could not show: how far each is from the ideal overdraw,
// and proof that the frames are the same.
#include <algorithm>

#include "depthcull/render.h"

namespace depthcull::render {

const char* mode_name(Mode mode) {
    switch (mode) {
    case Mode::overpaint: return "overpaint";
    case Mode::meshes: return "meshes";
    case Mode::optimized: return "optimized";
    }
    return "?";
}

ReconstructStatus build_meshes(Mode mode, const Scene& scene, const SceneAnalysis& analyses,
                               const ReconstructOptions& options, SceneMeshes* out, bool for_runtime) {
    // With element spans: GlRenderer samples each element through its own map.
    ReconstructOptions spanned = options;
    spanned.element_spans = !for_runtime || !scene.animations.empty();
    switch (mode) {
    case Mode::overpaint:
        *out = overpaint_meshes(scene, options.coverage_margin, true);
        return ReconstructStatus::ok;
    case Mode::meshes:
        return rectangle_meshes(scene, spanned, out);
    case Mode::optimized:
        return reconstruct_scene(scene, analyses, spanned, out);
    }
    return ReconstructStatus::invalid_scene;
}

ReconstructOptions exact_coverage(ReconstructOptions options) {
    if (options.coverage_margin == 0) options.coverage_margin = kCoverageMargin;
    return options;
}

namespace {

const char* status_text(ReconstructStatus status) {
    switch (status) {
    case ReconstructStatus::ok: return "ok";
    case ReconstructStatus::invalid_scene: return "invalid scene";
    case ReconstructStatus::too_many_depth_levels: return "more depth levels than a 24-bit depth buffer resolves";
    }
    return "?";
}

double median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

} // namespace

SceneMeasurement measure_scene(GlRenderer& renderer, const Scene& scene, const std::vector<ImageView>& images,
                               const SceneAnalysis& analyses, const MeasureOptions& options) {
    SceneMeasurement out;
    out.width = scene.viewport.width;
    out.height = scene.viewport.height;
    out.ideal_overdraw = ideal_overdraw(scene, images, options.keep_maps ? &out.ideal_map : nullptr).overdraw();
    renderer.set_images(images, scene.filter);

    std::vector<Mode> order{Mode::overpaint};
    for (Mode m : options.modes)
        if (std::find(order.begin(), order.end(), m) == order.end()) order.push_back(m);
    // Counts and timing draw the meshes as an engine gets them; the frames
    // compared come from the same meshes with coverage skirts
    // (exact_coverage), where nearest filtering must match exactly.
    std::vector<SceneMeshes> meshes(order.size()), exact(order.size());
    std::vector<int> slots, exact_slots;
    const ReconstructOptions exact_options = exact_coverage(options.reconstruct);
    const std::vector<TexelMap> maps = element_maps(scene);
    for (std::size_t i = 0; i < order.size(); ++i) {
        for (bool skirted : {false, true}) {
            SceneMeshes& m = skirted ? exact[i] : meshes[i];
            ReconstructStatus status = build_meshes(order[i], scene, analyses, skirted ? exact_options : options.reconstruct, &m);
            if (status != ReconstructStatus::ok)
                throw Error(std::string(mode_name(order[i])) + " meshes: " + status_text(status));
            if (i == 0 && !skirted) renderer.set_meshes(m, maps);
            (skirted ? exact_slots : slots).push_back(i == 0 && !skirted ? 0 : renderer.add_meshes(m, maps));
        }
    }

    std::vector<ModeMeasurement> measured(order.size());
    Image reference;
    const double pixels = double(out.width) * double(out.height);
    for (std::size_t i = 0; i < order.size(); ++i) {
        ModeMeasurement& m = measured[i];
        m.mode = order[i];
        renderer.select_meshes(slots[i]);
        m.counts = renderer.draw_counted();
        m.overdraw = pixels > 0 ? double(m.counts.samples_passed) / pixels : 0;
        m.cpu_overdraw = analyze_overdraw(meshes[i], options.keep_maps ? &m.map : nullptr).overdraw();
        renderer.select_meshes(exact_slots[i]);
        renderer.draw();
        Image frame = renderer.read_pixels();
        if (i == 0) reference = frame;
        m.diff = compare_images(reference.view(), frame.view());
        if (m.diff.pixels_differ) m.causes = classify_differences(reference.view(), exact[0], frame.view(), exact[i], &scene);
        if (options.keep_frames) m.frame = std::move(frame);
    }

    // Modes take turns frame by frame, each round starting with a different
    // one, so load from others on a shared machine and clock changes fall
    // on every mode alike rather than on whichever ran during them.
    if (options.frames > 0) {
        std::vector<std::vector<double>> ms(order.size());
        for (int round = -options.warmup; round < options.frames; ++round) {
            for (std::size_t k = 0; k < order.size(); ++k) {
                const std::size_t i = (std::size_t(round + options.warmup) + k) % order.size();
                renderer.select_meshes(slots[i]);
                const double t = renderer.time_frame();
                if (round >= 0) ms[i].push_back(t);
            }
        }
        for (std::size_t i = 0; i < order.size(); ++i) {
            measured[i].ms_median = median(ms[i]);
            measured[i].ms_min = *std::min_element(ms[i].begin(), ms[i].end());
        }
    }
    for (std::size_t i = 0; i < order.size(); ++i)
        if (std::find(options.modes.begin(), options.modes.end(), order[i]) != options.modes.end())
            out.modes.push_back(std::move(measured[i]));
    return out;
}

} // namespace depthcull::render
