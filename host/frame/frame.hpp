// The seam between the Renderer and the two paths: what is resident on the device for a scene,
// what one frame needs, and how stages report their device time. Both paths write the same
// visibility buffer (kernels/shared/visibility.h) and know nothing of each other.
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

struct InstancedScene; // render/instanced_scene.hpp

/// Collects the profiling events of a frame's kernels by stage name.
class StageRecorder {
public:
    /// Records `event` under `stage` (stages keep the order of their first event).
    void add(const std::string& stage, const cl::Event& event);
    /// Device time per stage in ms (end of last event - start of first, per stage), then clears;
    /// nullopt when the queue has no profiling (a wrapped queue made without it).
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

/// The kernel that clears keys to the background (kernels/visibility_clear.cl); make one per
/// pipeline, since cl::Kernel arguments are not safe to set from two threads.
cl::Kernel make_clear_kernel(Device::Impl& device);
/// Enqueues the clear of frame.keys to the background key (stage "clear").
void clear_keys(cl::Kernel& clear, Frame& frame);

/// A 1-D or 2-D global size rounded up to a multiple of the local size.
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

inline std::size_t round_up(std::size_t n, std::size_t multiple) { return (n + multiple - 1) / multiple * multiple; }

/// The raster path's first list of triangles to bin (elements): a frame that lists more grows it
/// and runs setup again (tests/oclgrind_test.cpp drives that path).
constexpr std::size_t raster_first_tri_capacity = std::size_t(1) << 12;

/// The raster tile edge (log2) that RenderOptions::tile_size asks for (0: the default).
int raster_tile_log2(const RenderOptions& options);
/// Whether the raster path runs by tile ownership on `info` under `options` (RasterAtomics).
bool raster_owned(const DeviceInfo& info, const RenderOptions& options);

/// The raster path. Its options name Square or Pixel: the Renderer resolves Auto first
/// (raster/raster_tune.hpp).
class RasterPipeline {
public:
    RasterPipeline(Device::Impl& device, const RenderOptions& options);
    ~RasterPipeline();
    /// Enqueues every kernel of the raster path for `frame` (the clear included) and returns
    /// without waiting; the Renderer waits and collects the stage times.
    void render(const DeviceScene& scene, Frame& frame);
    /// The same for a scene with instances, without its expansion: chunks of whole items of at
    /// most `chunk_triangles` triangles (or one item), each merged into the keys.
    void render(const InstancedScene& scene, Frame& frame, std::size_t chunk_triangles);

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

class RayPipeline {
public:
    RayPipeline(Device::Impl& device, const RenderOptions& options);
    ~RayPipeline();
    /// Builds the BVH of `scene` on the host and uploads it: one tree, or with instances one per
    /// prototype and a top level (ray/bvh_instances.hpp).
    void build(const Scene& scene, cl::CommandQueue& queue);
    /// Follows changed positions: refit or rebuild as options.bvh.update says; with instances,
    /// only the plain meshes' tree and the top level change.
    void update(const Scene& scene, cl::CommandQueue& queue);
    /// The primary rays' mapping (Packet or Single; RenderOptions' Auto traces packets until the
    /// Renderer resolves it): another one remakes the trace kernels.
    void set_mapping(RayMapping mapping);
    bool built() const;
    const BvhStats& stats() const;
    /// Enqueues the trace of one ray per pixel centre (through the BVH, or against every
    /// triangle when `brute`) writing every key of frame.keys.
    void render(const DeviceScene& scene, Frame& frame, bool brute);
    /// Enqueues one trace through the BVH for every view of `frame` (ray_trace_views).
    void render_views(ViewsFrame& frame);

    /// The resident BVH as ray_trace.cl reads it, for the ray queries (ray_query.cpp): 4-wide
    /// nodes, leaf triangles, the node count, the instances (empty without them), whether it has
    /// two levels (a scene with instances: ray_query.cl's CLVIS_INSTANCES) and the stack entries a
    /// walk needs. Valid once built.
    const cl::Buffer& nodes() const;
    const cl::Buffer& triangles() const;
    std::uint32_t node_count() const;
    const cl::Buffer& instances() const;
    bool two_level() const;
    int stack_entries() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

} // namespace clvis::detail
