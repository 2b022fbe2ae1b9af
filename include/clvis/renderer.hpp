// The Renderer: keeps a scene (and, for the ray path, its BVH) on a device between frames and
// answers the visibility question for a camera, by rasterization or by ray casting. Both paths
// write the same VisibilityBuffer. A Renderer is used from one thread at a time; two Renderers
// on two threads (sharing a Device or not) work independently.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/device.hpp>
#include <clvis/render_options.hpp>
#include <clvis/scene.hpp>
#include <clvis/visibility.hpp>

#include <memory>

namespace clvis {

namespace detail {
struct RendererAccess;
}

class Renderer {
public:
    /// Uploads the scene to the device and builds the kernels (from the program cache when
    /// possible). Throws Error(Limit) when the scene exceeds the device's memory,
    /// Error(Build) with the build log when a kernel fails to build.
    /// A moved-from Renderer throws Error(InvalidArgument) naming the call from every member.
    Renderer(Device device, const Scene& scene, RenderOptions options = {});
    /// The same, taking over `scene` instead of copying it (the meshes are then held once): for a
    /// caller that needs its Scene no more. `scene` is left empty.
    Renderer(Device device, Scene&& scene, RenderOptions options = {});
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;

    /// Renders into a new buffer of width x height.
    VisibilityBuffer render(const Camera& camera, int width, int height, Path path);
    /// Renders into `target` (its size), e.g. a buffer wrapped from the caller's cl_mem.
    void render(const Camera& camera, Path path, VisibilityBuffer& target);
    /// Renders `region` of a width x height image into `target`, which has the region's size:
    /// bit-identical to those pixels of the whole image's render. Throws Error(InvalidArgument)
    /// when the region is empty or leaves the image, or the target's size differs from it.
    void render(const Camera& camera, int width, int height, const Region& region, Path path,
                VisibilityBuffer& target);

    /// Re-uploads the meshes of `scene` (the one given at construction, changed since) whose
    /// positions or transform differ from the renderer's copy (compared by value), and refits or
    /// rebuilds the BVH as options().bvh.update says.
    void update(const Scene& scene);

    /// Builds what `path` needs before the first frame (the BVH, the kernels), so that the
    /// first render() is not charged for it.
    void prepare(Path path);

    const FrameTiming& last_frame() const;
    /// Statistics of the BVH as last built or refitted; zero before the ray path is used.
    const BvhStats& bvh_stats() const;
    const RenderOptions& options() const;
    const Device& device() const;
    /// The raster fine stage's mapping this Renderer runs and where it came from: options()'s,
    /// or for RasterMapping::Auto the tuner's choice for this device, made when first needed (the
    /// first raster frame, prepare(Path::Raster), or this call), measuring when nothing is cached.
    const RasterMappingChoice& raster_mapping();
    /// The ray path's primary-ray mapping this Renderer runs and where it came from: options()'s,
    /// or for RayMapping::Auto the tuner's choice for this device, made when first needed (the
    /// first Path::Ray frame or batch of views, prepare(Path::Ray), or this call), measuring when
    /// nothing is cached. The brute path and the ray queries need no mapping.
    const RayMappingChoice& ray_mapping();

    struct Impl;

private:
    friend struct detail::RendererAccess;
    Impl& checked(const char* call) const;
    std::unique_ptr<Impl> impl_;
};

} // namespace clvis
