// The Python module's shared pieces: the wrappers that give scenes and renderers a lock (Python
// threads run while the device works, the GIL released), the visibility result that owns its
// host arrays, and one bind_* function per file, called in order by module.cpp.
#pragma once

#include <clvis/clvis.hpp>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
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
};

/// A visibility buffer as Python sees it: host arrays shared with the NumPy arrays made from
/// them (which keep them alive alone), and the device buffer for shading, which keeps its Device
/// alive but not the Renderer that made it.
struct PyVisibility {
    std::shared_ptr<HostVisibility> host = std::make_shared<HostVisibility>();
    VisibilityBuffer device;         ///< empty for buffers made from arrays or files
    std::optional<Camera> camera;    ///< the camera it was rendered with
    std::optional<Path> path;
    FrameTiming timing;
    double call_seconds = 0;         ///< render and read-back as timed in C++ (the overhead benchmark)
};

/// Runs `f` with the GIL released and `lock` held (in that order).
template <class F>
auto unlocked(Lock& lock, F&& f)
{
    nb::gil_scoped_release nogil;
    std::lock_guard<std::mutex> guard(lock.mutex);
    return f();
}

/// 'raster', 'ray' or 'brute' as a Path; Error(InvalidArgument) listing them otherwise.
Path path_named(const std::string& name);

void bind_errors(nb::module_& m);
void bind_devices(nb::module_& m);
void bind_scene(nb::module_& m);
void bind_camera(nb::module_& m);
void bind_render(nb::module_& m);
void bind_referee(nb::module_& m);
/// Ray queries (queries.cpp) and visibility outputs (outputs.cpp) as Renderer methods.
void bind_ray_queries(nb::class_<PyRenderer>& r);
void bind_outputs(nb::class_<PyRenderer>& r);
void bind_image(nb::module_& m);

} // namespace clvis::python
