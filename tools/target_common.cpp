#include "target_common.h"

#include <cstdio>
#include <cstdlib>
#include <map>

#if defined(DEPTHCULL_HAVE_RENDER) && defined(DEPTHCULL_HAVE_RUNTIME)
#include "calibrate.h"
#include "depthcull/render.h"
#include "render_common.h"
#endif

namespace depthcull::cli {

CostProfile resolve_cli_target(const std::string& target, bool quiet) {
    if (target != "auto") return pipeline::resolve_target(target);
    // Resolved once per process: bench and report plan every scene.
    static std::map<std::string, CostProfile> resolved;
    if (auto it = resolved.find(target); it != resolved.end()) return it->second;
#if defined(DEPTHCULL_HAVE_RENDER) && defined(DEPTHCULL_HAVE_RUNTIME)
    // Pinned as bench and calibrate pin it, so the renderer measured is the one drawn.
    pin_lp_threads(-1);
    std::unique_ptr<render::GlHost> host;
    try {
        host = render::GlHost::create({}, render::GlApi::desktop);
    } catch (const render::NoContext& e) {
        throw CliError("--target auto: no OpenGL renderer found (" + std::string(e.what()) +
                       "): give --target llvmpipe, ipad1 or a profile file from `depthcull calibrate`");
    }
    const std::string renderer = host->description();
    const pipeline::AutoProfile found = pipeline::auto_profile(
        renderer, pipeline::default_profile_cache_dir(),
        [&] {
            if (!quiet)
                std::fprintf(stderr, "depthcull: --target auto: no profile for '%s' yet: calibrating it once (about a minute)\n",
                             renderer.c_str());
            return measure_profile(*host, false, quiet);
        },
        [](const std::string& line) { std::fprintf(stderr, "depthcull: warning: %s\n", line.c_str()); });
    if (!quiet)
        std::fprintf(stderr, "depthcull: --target auto: %s: profile %s (%s)\n", renderer.c_str(), found.profile.name.c_str(), found.how.c_str());
    return resolved[target] = found.profile;
#else
    (void)quiet;
    throw CliError("--target auto: this depthcull was built without the renderer (DEPTHCULL_BUILD_RENDER=OFF), so it cannot find the GL "
                   "renderer: give --target llvmpipe, ipad1 or a profile file");
#endif
}

void add_target_option(CLI::App& cmd, std::string& target) {
    cmd.add_option("--target", target,
                   "Optimize for this renderer: auto (the GL renderer found: its built-in profile, else one calibrated once and cached), "
                   "a built-in profile (llvmpipe, ipad1) or a profile JSON from `depthcull calibrate` "
                   "(vertex budget, opaque polygons and hidden elements chosen for the lowest predicted frame time)")
        ->type_name("PROFILE");
}

std::vector<std::string> target_inputs(const std::string& target) {
    CostProfile builtin;
    if (target.empty() || target == "auto" || builtin_profile(target, &builtin)) return {};
    return {target};
}

void add_target_stage_options(CLI::App& cmd, pipeline::PrepareOptions& prepare) {
    cmd.add_flag("!--no-clip-hidden", prepare.clip_hidden,
                 "With --target: do not clip hidden parts away at the opaque polygons in front (docs/ideal-frame.md)");
    cmd.add_flag("!--no-merge-opaque", prepare.merge_opaque,
                 "With --target: do not merge opaque tiles laid out as in their image into blocks (docs/ideal-frame.md)");
    cmd.add_flag("!--no-cover-plan", prepare.cover_plan,
                 "With --target: do not also plan with --opaque cover's pieces (docs/ideal-frame.md)");
    cmd.add_flag("!--no-depthless", prepare.depthless,
                 "With --target: always draw with a depth buffer, even where a frame without one is predicted faster (docs/ideal-frame.md)");
}

} // namespace depthcull::cli
