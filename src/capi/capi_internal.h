// Internal to src/capi: the handles behind depthcull.h's opaque types and
// the boundary every entry point passes through, where every exception is
// caught and turned into a status and a thread-local message.
#pragma once

#include <memory>
#include <new>
#include <span>
#include <string>

#include "depthcull/depthcull.h"
#include "depthcull/frame.h"
#include "depthcull/io.h"
#include "depthcull/scene.h"

// The C API's own types hold the library's values; they are the only place
// that knows the C++ API, so a change there changes only src/capi.
struct dc_analysis {
    // Shared with every scene element that uses it, so the caller may
    // destroy its handle while scenes still need the polygons.
    std::shared_ptr<const depthcull::ImageAnalysis> analysis;
};

struct dc_scene {
    depthcull::Scene scene;
    std::vector<std::shared_ptr<const depthcull::ImageAnalysis>> analyses; // per element; null for rect-only blends
    std::vector<depthcull::InsertionPoint> points; // dc_scene_add_insertion_point, for dc_reconstruct
};

struct dc_assembler {
    depthcull::FrameAssembler assembler;
};

struct dc_frame {
    depthcull::AssembledFrame frame;
    std::vector<depthcull::Sprite> sprites; // the C sprites converted, kept at capacity
    std::vector<std::span<const depthcull::Sprite>> lists; // dc_assemble_at: per point, a part of `sprites`
};

struct dc_meshes {
    // What the mesh files hold. Its seconds stay 0: files the C API writes
    // carry no timing (the CLI alone writes one), so they are the same
    // bytes on every run.
    depthcull::io::MeshesDocument document;
    // dc_meshes_info's stats.seconds: dc_reconstruct's wall time, or the
    // stats.seconds of the file read.
    double seconds = 0;
};

namespace depthcull::capi {

// Records the message (the parts joined) as this thread's last error and
// returns `status`. Never throws: it runs inside guard's handlers too.
dc_status fail(dc_status status, const char* message, const char* detail = nullptr) noexcept;
inline dc_status fail(dc_status status, const std::string& message) { return fail(status, message.c_str()); }

// Runs `body` (returning dc_status), mapping every exception to a status.
template <class Body>
dc_status guard(const char* function, Body&& body) noexcept {
    try {
        return body();
    } catch (const depthcull::Error& e) {
        return fail(DC_ERROR_IO, e.what());
    } catch (const std::bad_alloc&) {
        return fail(DC_ERROR_OUT_OF_MEMORY, function, "out of memory");
    } catch (const std::exception& e) {
        return fail(DC_ERROR_INTERNAL, function, e.what());
    } catch (...) {
        return fail(DC_ERROR_INTERNAL, function, "unknown exception");
    }
}

// Reconstruction statuses as C statuses, with the message.
dc_status reconstruct_status(const char* function, ReconstructStatus status);

} // namespace depthcull::capi
