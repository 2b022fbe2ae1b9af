// The Python module's shared pieces: the wrappers that give scenes and renderers a lock (Python
// threads run while the device works, the GIL released), the visibility result that owns its
// host arrays, and one bind_* function per file, called in order by module.cpp.
#pragma once

#include <clvis/clvis.hpp>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace clvis::python {

namespace nb = nanobind;

/// A mutex that a copy or a move does not share: the copy gets a fresh one.
struct Lock {
    std::mutex mutex;
    Lock() = default;
    Lock(const Lock&) {}
    Lock& operator=(const Lock&) { return *this; }
};

/// A Scene and its lock. Every use of `scene` that may run without the GIL takes the lock after
/// releasing the GIL (never the other way round), so that no two threads deadlock.
struct PyScene {
    Scene scene;
    Lock lock;
};

/// A Renderer, its lock, the triangle count of its scene (for visible sets) and its RayQuery,
/// made on the first ray query (it refers to `renderer`, which nanobind never moves).
struct PyRenderer {
    Renderer renderer;
    Lock lock;
    std::uint32_t triangles = 0;
    std::unique_ptr<RayQuery> query;
    /// The arrays of the last render() that made its own: reused by the next render of that
    /// size once nothing else refers to them (the caller dropped that result), so that a loop of
    /// renders allocates no host memory. Touched with the GIL held only.
    struct Spare {
        nb::object ids, depth;
        std::uint32_t* ids_data = nullptr;
        float* depth_data = nullptr;
        int width = 0, height = 0; ///< samples per pixel are the renderer's, fixed at construction
    } spare;
};

/// A visibility buffer as Python sees it: host arrays shared with the NumPy arrays made from
/// them (which keep them alive alone), or the caller's own arrays (render(out=...)), and the
/// device buffer for shading, which keeps its Device alive but not the Renderer that made it.
struct PyVisibility {
    /// Its size always; its arrays unless `ids_out` holds them.
    std::shared_ptr<HostVisibility> host = std::make_shared<HostVisibility>();
    /// The (H, W) NumPy arrays a render read back into (new ones, or the caller's with out=);
    /// empty for buffers made from arrays or files, whose arrays are `host`'s.
    nb::object ids_out, depth_out;
    VisibilityBuffer device;         ///< empty for buffers made from arrays, files or several devices
    std::optional<Camera> camera;    ///< the camera it was rendered with
    std::optional<Path> path;
    std::optional<Region> region;    ///< the part of the camera's image it holds, when not all
    FrameTiming timing;
    double call_seconds = 0;         ///< render and read-back as timed in C++ (the overhead benchmark)
    /// When that C++ part began and ended (steady_clock, which is Python's perf_counter on Linux).
    std::int64_t call_start_ns = 0, call_end_ns = 0;
};

/// The host arrays of `vis`: its own, or a copy of the caller's (out=) into `scratch`. Needs the GIL.
const HostVisibility& host_of(const PyVisibility& vis, HostVisibility& scratch);

/// Where a read-back goes: the caller's arrays (out=) or new ones, held by the Visibility.
struct ReadTarget {
    std::uint32_t* ids = nullptr;
    float* depth = nullptr; ///< null when not read
};

/// The arrays a render reads back into, kept in `vis` (ids_out, depth_out), of shape (H, W), or
/// (H, W, samples) with several samples per pixel: with `out` None, two new arrays, read-only to Python (numpy.empty: no page touched before the read;
/// Error(Limit) when the host cannot hold them); else the caller's, an (H, W) uint32 ids array or
/// (ids, depth) with depth an (H, W) float32 array or None, each writable, C-contiguous, of the
/// image's size (Error(InvalidArgument) naming which otherwise). Needs the GIL.
ReadTarget read_target(PyVisibility& vis, nb::handle out, int width, int height, int samples = 1);

/// The device buffer of a Visibility rendered whole by a Renderer, for `what` (resolve, shade,
/// ambient occlusion): Error(InvalidArgument) naming `what` for one made otherwise, or of a region
/// when `whole` (its pixels do not match its camera's image).
const VisibilityBuffer& device_buffer(const PyVisibility& vis, const char* what, bool whole = true);

/// Times `f`, one C++ part of a call: adds to vis.call_seconds, and spans vis.call_start_ns (the
/// first part's start) to vis.call_end_ns (the last part's end).
template <class V, class F>
void timed(V& vis, F&& f)
{
    const auto start = std::chrono::steady_clock::now();
    f();
    const auto end = std::chrono::steady_clock::now();
    const auto ns = [](std::chrono::steady_clock::time_point t) {
        return std::int64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count());
    };
    vis.call_seconds += std::chrono::duration<double>(end - start).count();
    if (vis.call_start_ns == 0) vis.call_start_ns = ns(start);
    vis.call_end_ns = ns(end);
}

/// Runs `f` with the GIL released and `lock` held (in that order).
template <class F>
auto unlocked(Lock& lock, F&& f)
{
    nb::gil_scoped_release nogil;
    std::lock_guard<std::mutex> guard(lock.mutex);
    return f();
}

void bind_errors(nb::module_& m);
void bind_devices(nb::module_& m);
void bind_scene(nb::module_& m);
void bind_camera(nb::module_& m);
/// Camera.rays (python/src/views.cpp), called by bind_camera.
void bind_camera_rays(nb::class_<Camera>& c);
/// read_views (python/src/views.cpp).
void bind_views(nb::module_& m);
void bind_render(nb::module_& m);
void bind_referee(nb::module_& m);
/// Ray queries (queries.cpp) and visibility outputs (outputs.cpp) as Renderer methods.
void bind_ray_queries(nb::class_<PyRenderer>& r);
void bind_outputs(nb::class_<PyRenderer>& r);
void bind_flow(nb::class_<PyRenderer>& r); // flow.cpp: Renderer.flow
void bind_image(nb::module_& m);
/// clvis.RayQuery (ray_query.cpp) and clvis.MultiDeviceRenderer (multi_device.cpp).
void bind_ray_query(nb::module_& m);
void bind_multi_device(nb::module_& m);
/// The RenderOptions of a Renderer's (or MultiDeviceRenderer's) keyword arguments after its
/// device(s) and scene, named as the command line names them (options.cpp's table; the rest
/// RenderOptions{}'s). TypeError for an unknown keyword (naming `what`, the class) or a value of
/// the wrong type; Error(InvalidArgument) from the library's names tables for an unknown name.
RenderOptions render_options(const nb::kwargs& given, const char* what);
/// nb::sig of such an __init__: "def __init__(self, <head>, *, tile: int = 0, ...) -> None".
const char* options_signature(const std::string& head);

} // namespace clvis::python
