// The frame layer under the two paths (host/frame/): what is resident on the device for a scene,
// what one frame needs, and how stages report their device time. Both paths write the same
// visibility buffer (kernels/shared/visibility.h) and know nothing of each other; each declares
// its pipeline in its own folder (raster/raster_pipeline.hpp, ray/ray_pipeline.hpp), and the
// Renderer (render/) drives them. This folder includes only runtime/, scene/ and shared/.
#pragma once

#include "runtime/cl.hpp"

#include "shared/camera.h"
#include "shared/region.h"
#include "shared/visibility.h"

#include <clvis/camera.hpp>
#include <clvis/device.hpp>
#include <clvis/render_options.hpp>
#include <clvis/scene.hpp>

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace clvis::detail {

/// The scene as uploaded once and shared by both paths.
struct DeviceScene {
    cl::Buffer positions;       ///< float x, y, z per vertex, world space, packed (vload3)
    cl::Buffer indices;         ///< uint, 3 per triangle, in id order
    cl::Buffer normals;         ///< float x, y, z per vertex, or a 1-element dummy when none
    bool has_normals = false;
    std::uint32_t triangle_count = 0;
    std::uint32_t vertex_count = 0;

    /// Sets the arguments that kernels reading the scene take in this order from `first`:
    /// positions, indices, normals, has_normals (int), triangle_count (uint).
    void set_args(cl::Kernel& kernel, cl_uint first) const;
};

/// The scene's world positions and indices with the bits of Scene::world_positions() and
/// world_indices(), without that cache (which would keep the expansion for the scene's life):
/// borrowed from the mesh where the scene is one untransformed item (an identity transform keeps
/// the bits), else expanded here and freed with this object. Moving it keeps the pointers.
struct WorldMesh {
    const float* positions = nullptr;      ///< 3 floats per vertex, world space
    const std::uint32_t* indices = nullptr; ///< 3 per triangle, into positions, id order
    std::vector<float> own_positions;       ///< the expansion, where made here
    std::vector<std::uint32_t> own_indices;
};
/// Error(InvalidArgument) as Scene::world_positions() gives it for a vertex that overflows float32.
WorldMesh world_mesh(const Scene& scene);
/// Writes item `item`'s world positions (transform applied: world_positions()'s bits) to `out`
/// (3 floats per vertex), with world_positions()'s overflow check.
void item_world_positions(const Scene& scene, std::size_t item, float* out);

struct InstancedScene; // frame/instanced_scene.hpp

/// Collects the profiling events of a frame's kernels by stage name.
class StageRecorder {
public:
    /// Records `event` under `stage` (stages keep the order of their first event).
    void add(const std::string& stage, const cl::Event& event);
    /// Device time per stage in ms: per run of consecutive events of the stage, end of its last
    /// event - start of its first, summed over the stage's runs (one run per stage in a one-pass
    /// frame; several when chunks or a redraw repeat it), then clears; nullopt when the queue has no profiling (a wrapped queue made without it).
    std::optional<std::vector<StageTiming>> collect();
    /// Device time per stage as the sum of its events' durations (a batch's kernels, however
    /// interleaved), then clears; nullopt when the queue has no profiling.
    std::optional<std::vector<StageTiming>> collect_sum();

private:
    std::vector<std::pair<std::string, cl::Event>> events_;
};

/// One frame's inputs.
struct Frame {
    cl::CommandQueue queue;
    clvis_camera_gpu gpu_camera{};   ///< the same in float32 for the kernels; sample_log2 set,
                                     ///< each path draws every sample (sets `sample` per launch)
    cl::Buffer keys;                 ///< width * height * samples keys, row 0 on top
    int width = 0, height = 0;       ///< of the region drawn (keys' size); gpu_camera has the image's
    clvis_region region{};           ///< the pixels drawn, in the image (shared/region.h)
    StageRecorder* stages = nullptr;
    int layers = 1;                  ///< RenderOptions::layers: `keys` holds this many layers of
                                     ///< width * height * samples keys, layer-major (shared/layers.h)
};

/// Many views of one size in one buffer: view v's keys start at key v * stride.
struct ViewsFrame {
    cl::CommandQueue queue;
    cl::Buffer cameras; ///< clvis_camera_gpu per view
    int views = 0, width = 0, height = 0;
    cl::Buffer keys;
    std::size_t stride = 0; ///< keys from one view to the next, >= width * height
    StageRecorder* stages = nullptr;
};

/// Converts a validated camera for a width x height image.
clvis_camera_gpu make_gpu_camera(const Camera& camera, int width, int height);


/// RenderOptions::cull as the kernels' CLVIS_CULL_* (shared/visibility.h), for every path.
inline int cull_mode(Cull cull)
{
    switch (cull) {
    case Cull::Back: return CLVIS_CULL_BACK;
    case Cull::Front: return CLVIS_CULL_FRONT;
    case Cull::None: break;
    }
    return CLVIS_CULL_NONE;
}

/// A global size rounded up to a multiple of the local size.
inline std::size_t round_up(std::size_t n, std::size_t multiple) { return (n + multiple - 1) / multiple * multiple; }

} // namespace clvis::detail
