// The state behind clvis::RayQuery, shared by ray_query.cpp (the queries) and ray_generate.cpp
// (rays made on the device from visibility buffers).
#pragma once

#include "render/renderer_impl.hpp"

#include <clvis/ray_query.hpp>

namespace clvis {

struct RayQuery::Impl {
    Renderer::Impl& r;
    RayQueryOptions options;

    /// A query kernel as last built for a stack size (per RayQueryKind).
    struct Built {
        cl::Kernel kernel;
        std::size_t group = 1; ///< work-items per work-group
        int stack = -1;        ///< CLVIS_RAY_STACK it was built with
        bool two_level = false; ///< a scene with instances: built with CLVIS_INSTANCES (brute: CLVIS_SCENE_ITEMS)
        int lanes = 1;          ///< CLVIS_QUERY_LANES: rays a work-item walks interleaved
        std::size_t per_item = 1; ///< rays a work-item answers
        /// PoCL's CPU device, one lane: work-groups of one work-item, each answering a run of rays
        /// (run_rays: its length by the batch); see kernel()
        bool runs = false;
    };
    Built built[3];
    /// All hits: per list length (the powers of two 1 .. 64, CLVIS_MAX_HITS) and whether counts
    /// are asked (CLVIS_ALL_COUNTS).
    Built built_all[7][2];
    /// The all-hits call in progress: hits kept per ray, and where the counts go (null: not asked).
    struct AllRequest {
        int max_hits = 1;
        std::uint32_t* counts = nullptr;
    } all;
    cl::Kernel generate_ao, generate_shadow;
    cl::Kernel generate_primary; ///< RayQuery::primary_rays (host/query/primary_rays.cpp)
    std::size_t capacity = 0;     ///< rays the staging buffers hold (the SoA stride)
    cl::Buffer staged_rays;       ///< capacity rays, AoS or SoA
    cl::Buffer staged_out;        ///< capacity hits, flags or counts; all hits: staged_out_bytes
    std::size_t staged_out_bytes = 0;
    cl::Buffer staged_counts;     ///< all hits: counts_capacity counts
    std::size_t counts_capacity = 0;
    cl::Buffer invalid;           ///< one uint: invalid rays seen by a batch
    /// Where the device works on host memory in place (Device::Impl::host_memory_in_place): the
    /// invalid rays' count is this word, counted by the kernel through invalid_direct, zeroed and
    /// read by the host around the batch without a copy.
    cl_uint invalid_word = 0;
    cl::Buffer invalid_direct;
    std::size_t generated_capacity = 0; ///< rays the generator's buffers hold
    cl::Buffer generated_rays;          ///< generated_capacity AoS rays (ray_generate.cpp)
    cl::Buffer generated_flags;         ///< generated_capacity any-hit flags

    /// Where a call's rays are, checked.
    struct Source {
        RayInput in;
        std::size_t stride = 0; ///< device SoA: elements per plane
    };
    /// Where its results go: exactly one of host (records), soa (closest hits), device.
    struct Sink {
        void* host = nullptr;
        const HitSoA* soa = nullptr;
        const DeviceResults* device = nullptr;
        std::size_t stride = 0; ///< device SoA
    };

    /// PoCL's CPU device reads and writes host memory where it lies: a call's host rays (AoS
    /// records, or SoA planes back to back in one array) and answers (AoS closest hits, flags,
    /// counts; not all hits, whose counts go through their own buffer) are buffers over the
    /// caller's arrays (CL_MEM_USE_HOST_PTR), so that no batch copies them through the staging
    /// buffers. Released when the call returns.
    struct HostWrap {
        cl::Buffer rays, out;
        DeviceRays device_rays;
        DeviceResults device_out;
    };
    /// Turns src's host records and dst's host answers into wrapped buffers where the device is
    /// PoCL's CPU device (one that refuses them keeps the staging path); dst may point into w.
    void wrap_host(RayQueryKind kind, Source& src, Sink& dst, HostWrap& w);

    Impl(Renderer& renderer, const RayQueryOptions& options);
    /// The kernel of `kind` (All: of the request in `all`) as built now.
    Built& built_for(RayQueryKind kind);
    cl::Kernel& kernel(RayQueryKind kind);
    /// Grows the staging buffers to hold `rays` rays and `out_per_ray` bytes of answers per ray
    /// (all hits: max_hits records; and counts when asked).
    void reserve(std::size_t rays, std::size_t out_per_ray = sizeof(HitRecord));
    /// Grows the generator's buffers to hold `rays` rays (kept from call to call).
    void reserve_generated(std::size_t rays);
    void batch(RayQueryKind kind, const Source& src, const Sink& dst, std::size_t first, std::size_t m,
               RayQueryStats& stats);
    RayQueryStats run(RayQueryKind kind, const Source& src, const Sink& dst);

    Source source(const RayInput& rays);
    Sink host_sink(void* out, std::size_t n);
    Sink device_sink(RayQueryKind kind, const DeviceResults& out, std::size_t n);
};

} // namespace clvis
