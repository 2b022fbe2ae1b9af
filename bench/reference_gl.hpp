// The rasterization reference: Mesa's OpenGL 3.3 core through EGL without a window (llvmpipe on a
// CPU). One glDrawElements of every triangle, in id order, into a framebuffer object with an
// R32UI colour attachment (gl_PrimitiveID = clvis triangle id) and a 32-bit float depth buffer.
#pragma once

#include "reference_result.hpp"

#include <clvis/camera.hpp>
#include <clvis/scene.hpp>

#include <memory>
#include <string>

namespace clvis::bench {

/// True when clvis_bench_refs was built with EGL and OpenGL (CLVIS_HAVE_GL).
bool gl_available() noexcept;

class GlReference {
public:
    /// Opens Mesa's surfaceless EGL platform (LP_NUM_THREADS set to `threads` before the display
    /// is first initialised in this process), makes a GL 3.3 core context current on the calling
    /// thread and uploads the scene. Throws std::runtime_error naming the failing call, or when
    /// GL was not built in. Render from the thread that constructed it.
    explicit GlReference(const Scene& scene, int threads = 2);
    ~GlReference();
    GlReference(const GlReference&) = delete;
    GlReference& operator=(const GlReference&) = delete;

    /// GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits); 3.3 (Core Profile) Mesa 22.3.6".
    std::string description() const;

    /// One untimed warm-up frame, then `repeats` timed frames (clear + draw + glFinish; the
    /// read-back is not timed), fewer past `budget_ms` (enough_frames). Ids are flipped to row 0
    /// on top; depth is the view depth recovered from the depth buffer. Throws
    /// std::runtime_error on a GL error.
    ReferenceResult render(const Camera& camera, int width, int height, int repeats, double budget_ms = 0);

    /// One camera and image size for interleaved timing (the reference must outlive it; use it
    /// from this thread), in a framebuffer of its own: frame() clears, draws and waits (glFinish);
    /// result() reads back ids with row 0 on top and view depth. Draws the warm-up frame; throws
    /// std::runtime_error naming the failing call.
    std::unique_ptr<ReferenceView> view(const Camera& camera, int width, int height);

private:
    struct Impl;
    class View;
    std::unique_ptr<Impl> impl_;
};

/// Sets up and renders in one call; failures land in ReferenceResult::error, never thrown.
ReferenceResult render_gl(const Scene& scene, const Camera& camera, int width, int height, int repeats,
                          int threads = 2);

} // namespace clvis::bench
