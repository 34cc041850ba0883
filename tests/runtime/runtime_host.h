// Hosting depthcull::runtime in the render library's headless EGL context
// (render::GlHost), the way an engine hosts it in its own.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "depthcull/render.h"
#include "depthcull/runtime.h"

namespace depthcull::test {

struct RuntimeHost {
    std::unique_ptr<render::GlHost> host;
    std::unique_ptr<runtime::Renderer> renderer;
    std::string error;
    bool no_context = false; // render::NoContext: skip, not fail

    // One per API for the whole test program: contexts are slow to make.
    // null with *why set when there is none; *no_context when no GL
    // context exists at all.
    static RuntimeHost* get(render::GlApi api, std::string* why, bool* no_context = nullptr) {
        static RuntimeHost hosts[2];
        RuntimeHost& h = hosts[api == render::GlApi::gles ? 1 : 0];
        if (!h.host && h.error.empty()) {
            try {
                h.host = render::GlHost::create({}, api);
                h.renderer = runtime::Renderer::create(&render::GlHost::get_proc_address, &h.error);
            } catch (const render::NoContext& e) {
                h.error = e.what();
                h.no_context = true;
            }
        }
        if (h.host) h.host->make_current();
        *why = h.error;
        if (no_context) *no_context = h.no_context;
        return h.renderer ? &h : nullptr;
    }

    // Draws `meshes` (plus `dynamic`) into a framebuffer the size of the
    // meshes' viewport and reads it back, top row first.
    Image frame(const SceneMeshes& meshes, std::span<const Draw> dynamic = {}) {
        EXPECT_EQ(renderer->set_meshes(meshes), runtime::Status::ok) << renderer->error();
        host->bind_framebuffer(meshes.viewport.width, meshes.viewport.height);
        runtime::FrameOptions options;
        options.clear_color = true;
        EXPECT_EQ(renderer->draw(runtime::camera_of(meshes.viewport, false), dynamic, options), runtime::Status::ok)
            << renderer->error();
        return host->read_pixels();
    }
};

// Skips the test when this machine has no GL context (no Mesa / EGL
// driver); fails when there is one but the runtime cannot use it.
#define DEPTHCULL_RUNTIME_HOST(var, api)                                                                                   \
    std::string var##_why;                                                                                                 \
    bool var##_no_context = false;                                                                                         \
    test::RuntimeHost* var = test::RuntimeHost::get(api, &var##_why, &var##_no_context);                                   \
    if (!var) {                                                                                                            \
        if (var##_no_context) GTEST_SKIP() << var##_why;                                                                   \
        FAIL() << var##_why;                                                                                               \
    }

} // namespace depthcull::test
