// The one GL renderer of the test_render program, made on first use and
// shared by its tests (making a context per test would cost seconds).
#pragma once

#include <memory>
#include <string>

#include "depthcull/render.h"

namespace depthcull::test {

// null with *why set when there is no renderer; *no_context when no GL
// context exists at all (skip rather than fail).
inline render::GlRenderer* shared_renderer(std::string* why, bool* no_context) {
    static std::string error;
    static bool none = false;
    static std::unique_ptr<render::GlRenderer> renderer = [] {
        try {
            return render::GlRenderer::create({});
        } catch (const render::NoContext& e) {
            error = e.what();
            none = true;
        } catch (const render::Error& e) {
            error = e.what();
        }
        return std::unique_ptr<render::GlRenderer>();
    }();
    *why = error;
    *no_context = none;
    return renderer.get();
}

} // namespace depthcull::test
