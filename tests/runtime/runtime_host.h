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

    // One per API for the whole test program: contexts are slow to make.
    static RuntimeHost* get(render::GlApi api, std::string* why) {
        static RuntimeHost hosts[2];
        RuntimeHost& h = hosts[api == render::GlApi::gles ? 1 : 0];
        if (!h.host && h.error.empty()) {
            h.host = render::GlHost::create({}, api, &h.error);
            if (h.host) h.renderer = runtime::Renderer::create(&render::GlHost::get_proc_address, &h.error);
        }
        if (h.host) h.host->make_current();
        *why = h.error;
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
    test::RuntimeHost* var = test::RuntimeHost::get(api, &var##_why);                                                      \
    if (!var) {                                                                                                            \
        if (var##_why.rfind("no OpenGL context", 0) == 0) GTEST_SKIP() << var##_why;                                       \
        FAIL() << var##_why;                                                                                               \
    }

} // namespace depthcull::test
