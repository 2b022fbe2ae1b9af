// The Renderer: keeps a scene (and, for the ray path, its BVH) on a device between frames and
// answers the visibility question for a camera, by rasterization or by ray casting. Both paths
// write the same VisibilityBuffer. A Renderer is used from one thread at a time; two Renderers
// on two threads (sharing a Device or not) work independently.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/device.hpp>
#include <clvis/scene.hpp>
#include <clvis/visibility.hpp>

#include <memory>
#include <string>
#include <vector>

namespace clvis {

namespace detail {
struct RendererAccess;
}

enum class Path {
    Raster, ///< project, clip, bin into tiles, rasterize with 64-bit atomic depth tests
    Ray,    ///< one ray per pixel centre through a BVH
    Brute,  ///< one ray per pixel centre against every triangle (small scenes)
};

const char* to_string(Path path) noexcept;
/// "raster", "ray" or "brute"; throws Error(InvalidArgument) otherwise.
Path path_from_string(const std::string& name);

enum class Cull { None, Back, Front };

/// How a BVH follows a mesh whose positions changed (Renderer::update).
enum class BvhUpdate { Refit, Rebuild };

struct BvhOptions {
    int max_leaf_size = 4; ///< triangles per leaf at most
    int sah_bins = 16;     ///< bins per axis of the binned SAH
    BvhUpdate update = BvhUpdate::Refit;
};

struct RenderOptions {
    int tile_size = 0;      ///< raster tile edge in pixels (a power of two); 0 picks the default
    Cull cull = Cull::None; ///< face culling; front faces are counter-clockwise on screen
    BvhOptions bvh;
};

struct StageTiming {
    std::string name; ///< e.g. "clear", "setup", "bin", "raster", "trace"
    double ms = 0;    ///< device time of the stage's kernels (profiling events)
};

struct FrameTiming {
    double frame_ms = 0;             ///< host wall time from the first enqueue to finish
    std::vector<StageTiming> stages; ///< in pipeline order
};

struct BvhStats {
    double build_ms = 0;   ///< host build (or refit) time, upload excluded
    double upload_ms = 0;
    std::size_t nodes = 0, leaves = 0;
    int depth = 0;
    double sah_cost = 0;
    bool refitted = false; ///< the last update refitted rather than rebuilt
};

class Renderer {
public:
    /// Uploads the scene to the device and builds the kernels (from the program cache when
    /// possible). Throws Error(Limit) when the scene exceeds the device's memory,
    /// Error(Build) with the build log when a kernel fails to build.
    Renderer(Device device, const Scene& scene, RenderOptions options = {});
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer& operator=(Renderer&&) noexcept;

    /// Renders into a new buffer of width x height.
    VisibilityBuffer render(const Camera& camera, int width, int height, Path path);
    /// Renders into `target` (its size), e.g. a buffer wrapped from the caller's cl_mem.
    void render(const Camera& camera, Path path, VisibilityBuffer& target);

    /// Re-uploads the meshes of `scene` (the one given at construction, changed since) whose
    /// revision moved, and refits or rebuilds the BVH as options().bvh.update says.
    void update(const Scene& scene);

    /// Builds what `path` needs before the first frame (the BVH, the kernels), so that the
    /// first render() is not charged for it.
    void prepare(Path path);

    const FrameTiming& last_frame() const;
    /// Statistics of the BVH as last built or refitted; zero before the ray path is used.
    const BvhStats& bvh_stats() const;
    const RenderOptions& options() const;
    const Device& device() const;

    struct Impl;

private:
    friend struct detail::RendererAccess;
    std::unique_ptr<Impl> impl_;
};

} // namespace clvis
