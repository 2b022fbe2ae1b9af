// The ray path's pipeline (ray_pipeline.cpp): the BVH built on the host and kept resident, and
// the trace kernels over the frame layer's scene and frame (frame/frame.hpp). Made and driven by
// the Renderer (render/); the ray queries (query/) read its resident BVH.
#pragma once

#include "frame/frame.hpp"

#include <clvis/device.hpp>
#include <clvis/render_options.hpp>
#include <clvis/scene.hpp>

#include <cstdint>
#include <memory>

namespace clvis::detail {

/// The ray path: through the BVH (ray_trace.cl, ray_trace_single.cl) or against every triangle
/// (ray_brute.cl). RayMapping::Auto is resolved by the Renderer (render/ray_tune.hpp).
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
    /// Enqueues the brute path for a scene with instances from its items (ray_brute.cl built with
    /// CLVIS_SCENE_ITEMS: the meshes once, a record per item, the expansion's keys).
    void render_brute(const InstancedScene& scene, Frame& frame);
    /// Enqueues one trace through the BVH for every view of `frame` (ray_trace_views).
    void render_views(ViewsFrame& frame);

    /// The resident BVH as ray_trace.cl reads it, for the ray queries (query/ray_query.cpp): wide
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
