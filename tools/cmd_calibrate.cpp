// depthcull calibrate: measures the current GL renderer term by term with
// depthcull::runtime (the plain sprite shader an engine runs) and writes a
// cost profile (docs/cost-model.md). Each term is a microbenchmark of
// synthetic meshes, timed as medians of single frames (glFinish each), in
// process CPU time (the profile's terms) and wall time (reported beside).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cli.h"
#include "depthcull/target.h"
#include "progress.h"

#if defined(DEPTHCULL_HAVE_RENDER) && defined(DEPTHCULL_HAVE_RUNTIME)
#include "calibrate.h"
#include "render_common.h"
#endif

#if defined(DEPTHCULL_HAVE_RENDER) && defined(DEPTHCULL_HAVE_RUNTIME)
#include "depthcull/render.h"
#include "depthcull/runtime.h"
#endif

namespace depthcull::cli {

#if defined(DEPTHCULL_HAVE_RENDER) && defined(DEPTHCULL_HAVE_RUNTIME)
namespace {

struct CalibrateArgs {
    std::string output;
    bool quick = false;
    int lp_threads = -1;
    bool quiet = false;
    std::string name;
    render::GlPlatform platform = render::GlPlatform::automatic;
};

void add_quad(Draw& d, double x0, double y0, double x1, double y1, float z) {
    const auto base = std::uint32_t(d.vertex_count());
    const double xs[4] = {x0, x1, x1, x0}, ys[4] = {y0, y0, y1, y1}, us[4] = {0, 1, 1, 0}, vs[4] = {0, 0, 1, 1};
    for (int k = 0; k < 4; ++k) d.vertices.insert(d.vertices.end(), {float(xs[k]), float(ys[k]), z, float(us[k]), float(vs[k]), 1, 1, 1, 1});
    d.indices.insert(d.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

void add_triangle(Draw& d, double ax, double ay, double bx, double by, double cx, double cy, float z) {
    const auto base = std::uint32_t(d.vertex_count());
    for (auto [x, y] : {std::pair{ax, ay}, std::pair{bx, by}, std::pair{cx, cy}})
        d.vertices.insert(d.vertices.end(), {float(x), float(y), z, 0.5f, 0.5f, 1, 1, 1, 1});
    d.indices.insert(d.indices.end(), {base, base + 1, base + 2});
}

struct Timing {
    double cpu_ms = 0, wall_ms = 0;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0 : v.size() % 2 ? v[v.size() / 2] : (v[v.size() / 2 - 1] + v[v.size() / 2]) / 2;
}

class Bench {
public:
    Bench(render::GlHost& host, int frames) : host_(host), frames_(frames) {
        std::string error;
        renderer_ = runtime::Renderer::create(&render::GlHost::get_proc_address, &error);
        if (!renderer_) throw CliError("calibrate: " + error);
        // Two textures, half transparent, so blending and texture switches are real.
        Image a, b;
        for (Image* img : {&a, &b}) {
            img->width = img->height = 64;
            img->rgba.assign(64 * 64 * 4, 128);
        }
        b.rgba[0] = 7;
        std::vector<ImageView> views{a.view(), b.view()};
        if (renderer_->upload_images(views, Filter::nearest) != runtime::Status::ok) throw CliError("calibrate: textures: " + renderer_->error());
    }
    Timing time(const SceneMeshes& m) {
        if (renderer_->set_meshes(m) != runtime::Status::ok) throw CliError("calibrate: meshes: " + renderer_->error());
        host_.bind_framebuffer(m.viewport.width, m.viewport.height);
        const runtime::Camera camera = runtime::camera_of(m.viewport, false);
        runtime::FrameOptions plain;
        plain.clear_color = true;
        std::vector<double> cpu, wall;
        for (int f = -2; f < frames_; ++f) {
            runtime::FrameTimes t;
            if (renderer_->time_frames(camera, 1, plain, &t) != runtime::Status::ok) throw CliError("calibrate: frame: " + renderer_->error());
            if (f >= 0) cpu.push_back(t.cpu_ms), wall.push_back(t.wall_ms);
        }
        return {median(cpu), median(wall)};
    }

private:
    render::GlHost& host_;
    int frames_;
    std::unique_ptr<runtime::Renderer> renderer_;
};

SceneMeshes frame(int w, int h, bool depth) {
    SceneMeshes m;
    m.viewport = {0, 0, w, h};
    m.depth_test = depth;
    return m;
}

Draw draw(int image, Pass pass, Blend blend = Blend::alpha) {
    Draw d;
    d.image = image;
    d.pass = pass;
    d.blend = blend;
    return d;
}

// The terms from the measured frames, for one clock (cpu or wall).
CostProfile solve(const std::vector<Timing>& t, bool cpu, int w, int h, int n_draws, int n_tris, int n_slivers, double sliver_len,
                  double sliver_frags, int layers) {
    auto ms = [&](std::size_t i) { return cpu ? t[i].cpu_ms : t[i].wall_ms; };
    enum { empty, empty_quarter, empty_depth, draws, tris, slivers, switches, blend, opaque, rejected };
    const double px = double(w) * h;
    CostProfile p;
    p.clear_color_ns_per_pixel = std::max(0.0, (ms(empty) - ms(empty_quarter)) * 1e6 / (px * 0.75));
    p.frame_us = std::max(0.0, ms(empty) * 1e3 - p.clear_color_ns_per_pixel * px / 1e3);
    p.clear_depth_ns_per_pixel = std::max(0.0, (ms(empty_depth) - ms(empty)) * 1e6 / px);
    const double tiny_us = std::max(0.0, (ms(tris) - ms(empty)) * 1e3 / n_tris);         // a one-pixel triangle
    const double sliver_us = std::max(0.0, (ms(slivers) - ms(empty)) * 1e3 / n_slivers);  // a long thin one
    const double tiny_perimeter = 2 + std::sqrt(2.0) + 0.0;                              // of a 1x1 right triangle
    const double draw_plus_tiny_us = std::max(0.0, (ms(draws) - ms(empty)) * 1e3 / n_draws);
    p.draw_call_us = std::max(0.0, draw_plus_tiny_us - tiny_us);
    p.texture_switch_us = std::max(0.0, (ms(switches) - ms(draws)) * 1e3 / n_draws);
    p.fragment_blend_ns = std::max(0.0, ((ms(blend) - ms(empty)) * 1e6 - 2 * layers * tiny_us * 1e3) / (layers * px));
    p.triangle_perimeter_ns_per_pixel =
        std::max(0.0, (sliver_us - tiny_us) * 1e3 - sliver_frags * p.fragment_blend_ns) / (2 * sliver_len - tiny_perimeter);
    p.triangle_us = std::max(0.0, tiny_us - p.triangle_perimeter_ns_per_pixel * tiny_perimeter / 1e3);
    p.fragment_opaque_ns = std::max(0.0, (ms(opaque) - ms(empty_depth)) * 1e6 / (layers * px));
    // One opaque layer written, then `layers` blend layers rejected behind it.
    p.fragment_rejected_ns = std::max(0.0, ((ms(rejected) - ms(empty_depth)) * 1e6 - px * p.fragment_opaque_ns) / (layers * px));
    return p;
}

// The microbenchmarks' sizes: --quick's take seconds, the full ones about
// a minute.
struct Sizes {
    int w = 0, h = 0;
    int frames = 0;
    int n_draws = 0, n_tris = 0, n_slivers = 0;
    int layers = 0;
    double sliver_len = 0, sliver_width = 1.0 / 16;
};

Sizes sizes(bool quick) {
    Sizes s;
    s.w = quick ? 256 : 1024;
    s.h = quick ? 192 : 768;
    s.frames = quick ? 3 : 41;
    // Not fewer draws: below about 800 per frame, llvmpipe's per-switch
    // state lands in memory glibc maps fresh every frame (page faults; with
    // glibc.malloc.mmap_threshold raised it does not), and a switch
    // measures 100+ us instead of the 1.5 .. 3.4 us a full run and the
    // corpus frames give.
    s.n_draws = quick ? 1000 : 4000;
    s.n_tris = quick ? 2000 : 40000;
    s.n_slivers = quick ? 200 : 4000;
    s.layers = quick ? 2 : 8;
    s.sliver_len = quick ? 128 : 512;
    return s;
}

// Step 1: the empty frames and the vertex-side cases (draw calls,
// triangles, slivers, texture switches), in solve's order.
void add_vertex_cases(const Sizes& z, std::vector<SceneMeshes>& cases) {
    const int w = z.w, h = z.h;
    cases.push_back(frame(w, h, false));         // empty
    cases.push_back(frame(w / 2, h / 2, false)); // empty, a quarter of the pixels
    cases.push_back(frame(w, h, true));          // empty with the depth clear
    SceneMeshes m = frame(w, h, false); // draw calls: one one-pixel triangle each, one texture
    for (int i = 0; i < z.n_draws; ++i) {
        m.draws.push_back(draw(0, Pass::blend));
        const double x = i % (w - 2), y = (i / (w - 2)) % (h - 2);
        add_triangle(m.draws.back(), x, y, x + 1, y, x, y + 1, 0);
    }
    cases.push_back(m);
    SceneMeshes t = frame(w, h, false); // triangles: one-pixel ones in one draw
    t.draws.push_back(draw(0, Pass::blend));
    for (int i = 0; i < z.n_tris; ++i) {
        const double x = i % (w - 2), y = (i / (w - 2)) % (h - 2);
        add_triangle(t.draws.back(), x, y, x + 1, y, x, y + 1, 0);
    }
    cases.push_back(t);
    SceneMeshes s = frame(w, h, false); // slivers: long perimeter, few fragments
    s.draws.push_back(draw(0, Pass::blend));
    for (int i = 0; i < z.n_slivers; ++i) {
        const double y = 1 + (i % (h - 2)), x = (i / (h - 2)) % 8;
        add_triangle(s.draws.back(), x, y, x + z.sliver_len, y + 0.5, x, y + z.sliver_width, 0);
    }
    cases.push_back(s);
    SceneMeshes sw = m; // texture switches: the same draws alternating textures
    for (std::size_t i = 0; i < sw.draws.size(); ++i) sw.draws[i].image = int(i % 2);
    cases.push_back(sw);
}

// Step 2: the fragment-side cases (blended, opaque, rejected), after them.
void add_fragment_cases(const Sizes& z, std::vector<SceneMeshes>& cases) {
    const int w = z.w, h = z.h, layers = z.layers;
    SceneMeshes b = frame(w, h, false); // blended fragments
    for (int k = 0; k < layers; ++k) {
        b.draws.push_back(draw(0, Pass::blend));
        add_quad(b.draws.back(), 0, 0, w, h, 0);
    }
    cases.push_back(b);
    SceneMeshes o = frame(w, h, true); // opaque-pass fragments, each layer nearer: all written
    for (int k = 0; k < layers; ++k) {
        o.draws.push_back(draw(0, Pass::opaque));
        add_quad(o.draws.back(), 0, 0, w, h, float(k + 1) / float(layers + 2));
    }
    cases.push_back(o);
    SceneMeshes r = frame(w, h, true); // one opaque layer in front, blend layers rejected behind it
    r.draws.push_back(draw(0, Pass::opaque));
    add_quad(r.draws.back(), 0, 0, w, h, 0.9f);
    for (int k = 0; k < layers; ++k) {
        r.draws.push_back(draw(0, Pass::blend));
        add_quad(r.draws.back(), 0, 0, w, h, 0.1f);
    }
    cases.push_back(r);
}

// Step 3: each case's median frame time.
std::vector<Timing> time_cases(Bench& bench, const std::vector<SceneMeshes>& cases, bool quiet) {
    Progress progress("calibrate", "microbenchmarks", 2 * cases.size(), quiet);
    // Two rounds, taking each case's lower median: a shared machine's load
    // falls on whichever case it hits. --quick too: its frames are short, so
    // one busy moment can hide a whole term (a CI run once measured
    // triangles free).
    std::vector<Timing> t;
    for (const SceneMeshes& m : cases) {
        t.push_back(bench.time(m));
        progress.add();
    }
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const Timing again = bench.time(cases[i]);
        t[i].cpu_ms = std::min(t[i].cpu_ms, again.cpu_ms);
        t[i].wall_ms = std::min(t[i].wall_ms, again.wall_ms);
        progress.add();
    }
    progress.finish();
    return t;
}

// Step 4: the terms for one clock.
CostProfile solve(const std::vector<Timing>& t, bool cpu, const Sizes& z) {
    // Sliver fragments: rows crossed where the sliver is at least a pixel centre wide (about half its length).
    const double sliver_frags = z.sliver_len * z.sliver_width; // area of the sliver; 0.5 px tall over its length
    return solve(t, cpu, z.w, z.h, z.n_draws, z.n_tris, z.n_slivers, z.sliver_len, sliver_frags, z.layers);
}

// The terms a software renderer always spends CPU time on that this run
// measured as free: its load hid them (each is a difference of two timings).
std::vector<std::string> terms_lost_in_noise(const CostProfile& p) {
    std::vector<std::string> lost;
    if (p.draw_call_us <= 0) lost.push_back("draw call");
    if (p.triangle_us + p.triangle_perimeter_ns_per_pixel <= 0) lost.push_back("triangle");
    if (p.fragment_opaque_ns <= 0) lost.push_back("opaque fragment");
    if (p.fragment_blend_ns <= 0) lost.push_back("blended fragment");
    if (p.fragment_rejected_ns <= 0) lost.push_back("rejected fragment");
    return lost;
}

} // namespace

CostProfile measure_profile(render::GlHost& host, bool quick, bool quiet, CostProfile* wall) {
    const Sizes z = sizes(quick);
    Bench bench(host, z.frames);
    std::vector<SceneMeshes> cases;
    add_vertex_cases(z, cases);
    add_fragment_cases(z, cases);
    const std::vector<Timing> t = time_cases(bench, cases, quiet);
    CostProfile p = solve(t, true, z);
    if (wall) *wall = solve(t, false, z);
    p.name = host.is_software() ? "calibrated-software" : "calibrated";
    p.renderer = host.description() + ", LP_NUM_THREADS=" + (std::getenv("LP_NUM_THREADS") ? std::getenv("LP_NUM_THREADS") : "");
    p.source = std::string("depthcull calibrate") + (quick ? " --quick" : "") + ": process CPU ms, medians of " +
               std::to_string(z.frames) + " frames per microbenchmark at " + std::to_string(z.w) + "x" + std::to_string(z.h);
    std::string what;
    if (!profile_is_complete(p, &what)) throw CliError("calibrate: the measured term " + what + " is not a finite number >= 0");
    if (host.is_software()) {
        // Still a complete profile, but one whose plans take those costs
        // for free: say so, whatever --quiet says.
        const std::vector<std::string> lost = terms_lost_in_noise(p);
        if (!lost.empty()) {
            std::string names;
            for (const std::string& n : lost) names += (names.empty() ? "" : ", ") + n;
            std::fprintf(stderr, "warning: calibrate: the %s cost measured 0 on a software renderer (this machine's load hid it); plans made with "
                         "this profile take it for free: measure again%s on a quieter machine\n", names.c_str(), quick ? " without --quick" : "");
        }
    }
    return p;
}

namespace {

void run_calibrate(const CalibrateArgs& args) {
    pin_lp_threads(args.lp_threads);
    auto host = open_host(args.platform);
    CostProfile wall;
    CostProfile p = measure_profile(*host, args.quick, args.quiet, &wall);
    if (!args.name.empty()) p.name = args.name;
    std::string text = pipeline::profile_to_json(p);
    // The wall-clock terms beside, for reference (not read back as terms).
    std::string wall_json = pipeline::profile_to_json(wall);
    const std::size_t terms_at = wall_json.find("\"frame_us\"");
    wall_json = "{\n    " + wall_json.substr(terms_at);
    for (std::size_t pos = 0; (pos = wall_json.find("\n  \"", pos)) != std::string::npos; pos += 3) wall_json.insert(pos + 1, "  ");
    wall_json.erase(wall_json.find_last_not_of("\n}") + 1);
    text.erase(text.find_last_of('}'));
    text.erase(text.find_last_not_of("\n") + 1);
    text += ",\n  \"wall\": " + wall_json + "\n  }\n}\n";
    if (args.output.empty() || args.output == "-") std::fputs(text.c_str(), stdout);
    else io::write_file_atomic(args.output, text);
    if (!args.quiet) {
        std::fprintf(stderr,
                     "depthcull: calibrate: %s: frame %.1f us, clear %.3f + %.3f ns/px, draw %.3f us (+%.3f texture), triangle %.3f us + %.2f "
                     "ns/px perimeter, fragment opaque %.2f / blend %.2f / rejected %.2f ns (CPU)%s%s\n",
                     p.renderer.c_str(), p.frame_us, p.clear_color_ns_per_pixel, p.clear_depth_ns_per_pixel, p.draw_call_us, p.texture_switch_us,
                     p.triangle_us, p.triangle_perimeter_ns_per_pixel, p.fragment_opaque_ns, p.fragment_blend_ns, p.fragment_rejected_ns,
                     args.output.empty() || args.output == "-" ? "" : "; written to ", args.output.empty() || args.output == "-" ? "" : args.output.c_str());
    }
}

} // namespace

void add_calibrate_command(CLI::App& app) {
    auto args = std::make_shared<CalibrateArgs>();
    auto* cmd = app.add_subcommand("calibrate", "Measure this GL renderer term by term and write a cost profile for --target");
    cmd->add_option("-o,--output", args->output, "Write the profile JSON here (atomically); default stdout")->type_name("PROFILE.json");
    cmd->add_flag("--quick", args->quick, "A few seconds at 256x192 (a smoke test; the numbers are rough)");
    cmd->add_option("--name", args->name, "The profile's name (default: calibrated)");
    cmd->add_option("--lp-threads", args->lp_threads, "LP_NUM_THREADS for llvmpipe (default: the environment's, else 1)")->check(CLI::Range(0, 64));
    cmd->add_option("--gl", args->platform, "EGL platform: auto, surfaceless, device")
        ->transform(choice<render::GlPlatform>({{"auto", render::GlPlatform::automatic},
                                                {"surfaceless", render::GlPlatform::surfaceless},
                                                {"device", render::GlPlatform::device}}))
        ->default_str("auto");
    add_quiet_flag(*cmd, args->quiet);
    cmd->callback([args] { run_calibrate(*args); });
}

#else

void add_calibrate_command(CLI::App& app) {
    auto* cmd = app.add_subcommand("calibrate", "Measure this GL renderer (not in this build)");
    cmd->allow_extras();
    cmd->callback([] { throw CliError("calibrate: this depthcull was built without the renderer (DEPTHCULL_BUILD_RENDER=OFF)"); });
}

#endif

} // namespace depthcull::cli
