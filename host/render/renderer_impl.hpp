// The state behind clvis::Renderer, shared by the files of render/ (renderer.cpp, batch.cpp,
// shading.cpp, resolve.cpp) and the ray queries above it (query/ray_query_impl.hpp).
#pragma once

#include "frame/frame.hpp"
#include "frame/instanced_scene.hpp"
#include "raster/raster_pipeline.hpp"
#include "ray/ray_pipeline.hpp"
#include "runtime/cl_runtime.hpp"

#include <clvis/renderer.hpp>

#include <memory>
#include <optional>

namespace clvis {

namespace detail {
struct CornerCache; // render/attribute_access.hpp
}

struct Renderer::Impl {
    Device device;
    RenderOptions options;
    Scene scene; ///< the host copy: BVH builds and refits read it
    cl::CommandQueue queue;
    detail::DeviceScene gpu; ///< the expansion on the device: read it through scene_buffers()
    bool uploaded = false;
    bool instanced = false; ///< the scene has instances: the raster path reads `items`
    detail::InstancedScene items; ///< the meshes once and a record per item: read it through item_buffers()
    bool items_uploaded = false;
    std::size_t raster_chunk = detail::default_raster_chunk; ///< triangles per chunk of items
    std::unique_ptr<detail::RasterPipeline> raster;
    std::unique_ptr<detail::RayPipeline> ray;
    FrameTiming last;
    BvhStats no_bvh;
    detail::StageRecorder stages;
    std::shared_ptr<detail::CornerCache> corners; ///< named attributes on the device, made when resolved

    Device::Impl& dev() { return detail::DeviceAccess::of(device, "Renderer"); }

    /// Error(Limit) where the plain scene's positions and indices do not fit on the device.
    void check_scene_fits();
    void upload_all();
    /// The expanded scene on the device, uploaded on first use: the ray path never needs it (its
    /// BVH holds the triangles; a scene of 10,000 instances need not fit expanded).
    detail::DeviceScene& scene_buffers()
    {
        if (!uploaded) upload_all();
        uploaded = true;
        return gpu;
    }
    void upload_positions(std::size_t item, std::size_t first_vertex);
    /// The scene with instances without its expansion, uploaded on first use (again after an update).
    detail::InstancedScene& item_buffers()
    {
        if (!items_uploaded) items.upload(scene, dev(), queue);
        items_uploaded = true;
        return items;
    }
    /// The ray pipeline, made on first use, nothing built (the brute path needs no more).
    detail::RayPipeline& ray_pipeline();
    /// The ray pipeline with its BVH built (the ray queries: they need no primary-ray mapping).
    detail::RayPipeline& ray_pipeline_with_bvh();
    /// The ray pipeline for primary rays (Path::Ray's frames and views): the ray mapping resolved
    /// and applied, then the BVH built (so the build makes the chosen trace kernel).
    detail::RayPipeline& primary_ray_pipeline();
    std::optional<RayMappingChoice> ray_choice; ///< options.ray_mapping resolved, once needed
    /// The ray mapping, resolved on first use (Auto: the tuner, render/ray_tune.hpp).
    const RayMappingChoice& ray_mapping();
    std::optional<RasterMappingChoice> raster_choice; ///< options.raster_mapping resolved, once needed
    /// The raster mapping, resolved on first use (Auto: the tuner, render/raster_tune.hpp).
    const RasterMappingChoice& raster_mapping();
    /// The raster path, made on first use with the resolved mapping.
    detail::RasterPipeline& raster_pipeline();
    /// FrameTiming::raster_atomics of a frame just drawn on `path`.
    RasterAtomics raster_depth_test(Path path) const
    {
        if (path != Path::Raster || !raster) return RasterAtomics::Auto;
        return raster->frame_owned() ? RasterAtomics::Off : RasterAtomics::On;
    }
    /// Enqueues one frame of Path::Brute (the ray pipeline made): a scene with instances from its
    /// items (never the expansion), a plain one from its resident arrays.
    void render_brute(detail::Frame& frame);
    /// Makes what a frame of `path` needs (its pipeline, mapping and BVH) before it is timed.
    void prepare(Path path);
    /// One frame of `path`: `region` of a width x height image into `target` (the region's
    /// size), for a camera already validated.
    void render(const Camera& camera, int width, int height, const Region& region, Path path,
                VisibilityBuffer& target);
    /// Renderer::update inside its error boundary.
    void update(const Scene& scene);
};

namespace detail {
/// Library code beside the Renderer (shading) reaches its state through this.
struct RendererAccess {
    static Renderer::Impl& of(Renderer& renderer, const char* call) { return renderer.checked(call); }
};
} // namespace detail

} // namespace clvis
