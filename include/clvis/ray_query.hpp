// Ray queries on the device through a Renderer's scene and BVH: closest hit, any hit (occlusion)
// and hit count for any batch of rays, from host arrays or from the caller's cl_mem, results into
// the caller's storage. Batches of any size are split internally so device memory stays bounded.
// Also the first users of the queries: ambient occlusion and shadow rays generated on the device
// from a visibility buffer.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/math.hpp>
#include <clvis/rays.hpp>
#include <clvis/renderer.hpp>
#include <clvis/visibility.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace clvis {

enum class RayLayout {
    AoS, ///< rays: 8 floats per ray; hits: 16-byte records
    SoA, ///< one plane per field: field k of record i at element k * stride + i
};

/// Rays in a device buffer of the renderer's context.
struct DeviceRays {
    cl_mem buffer = nullptr;
    RayLayout layout = RayLayout::AoS;
    std::size_t count = 0;  ///< rays
    std::size_t stride = 0; ///< SoA: elements per plane (>= count); 0 means count
};

/// The rays of one call, wherever they are: `{pointer, n}` (records), `{RaySoA, n}` (one array
/// per field) or a DeviceRays.
struct RayInput {
    RayInput(const RayRecord* rays, std::size_t n) : records(rays), count(n) {}
    RayInput(const RaySoA& rays, std::size_t n) : fields(rays), soa(true), count(n) {}
    RayInput(const DeviceRays& rays) : device(rays), on_device(true), count(rays.count) {}

    const RayRecord* records = nullptr;
    RaySoA fields{};
    bool soa = false;
    DeviceRays device{};
    bool on_device = false;
    std::size_t count = 0;
};

/// Where results go on the device: closest hits (AoS records or SoA planes of `stride`), or one
/// uint8 (any) or uint32 (count) per ray.
struct DeviceResults {
    cl_mem buffer = nullptr;
    RayLayout layout = RayLayout::AoS; ///< closest hits only
    std::size_t stride = 0;            ///< SoA: elements per plane; 0 means the ray count
};

struct RayQueryOptions {
    std::size_t batch_rays = std::size_t(1) << 20; ///< rays per kernel launch at most (bounds the
                                                   ///< staging buffers: 48 bytes per ray; on PoCL's
                                                   ///< CPU device the kernels read host records, or
                                                   ///< planes back to back in one array, and write
                                                   ///< closest hit records, flags and counts in place)
    bool brute = false; ///< test every triangle instead of walking the BVH (tests, tiny scenes)
    int lanes = 0;      ///< rays one work-item walks interleaved, 1..8, so their node loads
                        ///< overlap (pays where the tree misses the caches); 0 means 1
};

struct AoOptions {
    int rays = 8;                 ///< per pixel, cosine-weighted about the face normal, 1..1024
    float distance = 0;           ///< ray length in world units; 0: 10% of the scene's diagonal
    std::uint64_t seed = 1;       ///< same seed, same rays
};

/// Per-pixel results of rays generated from a visibility buffer (row 0 on top).
struct PixelRays {
    int width = 0, height = 0;
    std::vector<float> value; ///< AO: unoccluded fraction in [0, 1]; shadow: 1 lit, 0 shadowed;
                              ///< background pixels 1
    RayQueryStats stats;
};

class RayQuery {
public:
    /// Shares `renderer`'s resident scene and BVH (building it when the ray path has not yet),
    /// and builds the query kernels. The Renderer must outlive the RayQuery and not be moved;
    /// Renderer::update() is seen by later queries.
    explicit RayQuery(Renderer& renderer, RayQueryOptions options = {});
    ~RayQuery();
    RayQuery(RayQuery&&) noexcept;
    RayQuery& operator=(RayQuery&&) noexcept;

    /// The nearest hit per ray (a miss: id background_id, t = +inf, u = v = 0).
    RayQueryStats closest(const RayInput& rays, HitRecord* hits);
    RayQueryStats closest(const RayInput& rays, const HitSoA& hits);
    RayQueryStats closest(const RayInput& rays, const DeviceResults& hits);

    /// The primary rays of `camera` for a width x height image at `samples` per pixel, written on
    /// the device into `out` (a buffer of the renderer's context holding at least width * height *
    /// samples rays, AoS or SoA) by the kernels' own operations: the records clvis::primary_rays
    /// (include/clvis/primary_rays.hpp) computes on the host, bit for bit, with no transfer, so
    /// that closest() of them gives the ray path's render (CONVENTIONS.md "Primary rays as
    /// arrays"). Returns when they are written. Throws Error(InvalidArgument) as primary_rays
    /// does, and for a buffer too small or of another context.
    void primary_rays(const Camera& camera, int width, int height, int samples, const DeviceRays& out);

    /// 1 per ray with a hit in [tmin, tmax], else 0.
    RayQueryStats occluded(const RayInput& rays, std::uint8_t* flags);
    RayQueryStats occluded(const RayInput& rays, const DeviceResults& flags);

    /// Crossings of the surface per ray in [tmin, tmax]; on a closed mesh, odd from inside.
    RayQueryStats count(const RayInput& rays, std::uint32_t* counts);
    RayQueryStats count(const RayInput& rays, const DeviceResults& counts);

    /// All hits (CONVENTIONS.md "Depth layers"): each ray's max_hits (1 .. ray_query_max_hits)
    /// nearest hits in [tmin, tmax], edges inclusive as closest() (a ray through an edge shared by
    /// two triangles meets both), ordered by t then id, into hits[i * max_hits .. i * max_hits +
    /// max_hits - 1]; the slots past a ray's last hit are misses as closest() writes them. With
    /// `counts` (rays.count of them), the number of all hits of each ray, edges inclusive, which
    /// may exceed max_hits (not count()'s half-open crossings; asking for it walks every box the
    /// ray meets, where without it the walk prunes against the max_hits-th nearest hit).
    RayQueryStats all(const RayInput& rays, int max_hits, HitRecord* hits, std::uint32_t* counts = nullptr);

    /// Ambient occlusion of every pixel of `vis` (made with `camera`): options.rays rays from
    /// each visible point, on the side facing the camera. Rays are made and traced for covered
    /// pixels only (stats.rays counts those).
    PixelRays ambient_occlusion(const VisibilityBuffer& vis, const Camera& camera, const AoOptions& options = {});
    /// The rays of ambient_occlusion(), options.rays per pixel, pixels in row order; a background
    /// pixel's rays, which ambient_occlusion() does not trace, have a zero direction (invalid:
    /// answered as misses).
    std::vector<RayRecord> ambient_occlusion_rays(const VisibilityBuffer& vis, const Camera& camera,
                                                  const AoOptions& options = {});
    /// Whether each visible point of `vis` sees the point light at `light` (world space).
    PixelRays shadows(const VisibilityBuffer& vis, const Camera& camera, const Vec3& light);

    const RayQueryOptions& options() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

} // namespace clvis
