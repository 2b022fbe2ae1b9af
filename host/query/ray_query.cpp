// Ray queries through a Renderer's resident scene and BVH: uploads the caller's rays batch by
// batch (or reads them from the caller's cl_mem), launches kernels/ray_query.cl and reads the
// answers back into the caller's storage. Batches keep device memory bounded whatever the count.
// The rays generated from visibility buffers (ambient occlusion, shadows) are in ray_generate.cpp.
#include "query/ray_query_impl.hpp"

#include "shared/ray_query.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <string>

namespace clvis {

using namespace detail;

static_assert(sizeof(clvis_ray_rec) == sizeof(RayRecord), "layout shared with kernels/shared/ray_query.h");
static_assert(sizeof(clvis_hit_rec) == sizeof(HitRecord), "layout shared with kernels/shared/ray_query.h");

bool ray_is_valid(const RayRecord& ray) noexcept
{
    clvis_ray_rec r;
    std::memcpy(&r, &ray, sizeof r);
    return clvis_ray_valid(r) != 0;
}

namespace {

/// The traversal stack grows in steps of this many entries (each step is one program build).
constexpr int stack_step = 16;
/// Work-items per work-group at most.
constexpr std::size_t group_items = 64;
/// Rays per work-item per lane when RayQueryOptions::lanes > 1 (a lane whose ray is answered
/// takes the work-item's next one).
constexpr int items_per_lane = 4;
/// PoCL's CPU device (Built::runs): rays a one-work-item group answers at most, and the groups each
/// compute unit gets at least before runs shorten.
constexpr std::size_t run_max = 64;
constexpr std::size_t runs_per_unit = 16;

/// The run of rays per work-item for a batch of m rays on `units` compute units.
std::size_t run_rays(std::size_t m, unsigned units)
{
    std::size_t groups = std::size_t(std::max(1u, units)) * runs_per_unit;
    return std::clamp<std::size_t>(m / groups, 1, run_max);
}

static_assert(CLVIS_MAX_ALL_HITS == ray_query_max_hits, "the limit shared with kernels/shared/ray_query.h");

/// Bytes of answers per ray (all hits: per hit kept).
std::size_t result_bytes(RayQueryKind kind)
{
    return kind == RayQueryKind::Closest || kind == RayQueryKind::All ? 16 : kind == RayQueryKind::Any ? 1 : 4;
}

/// The list length all hits are built for: the power of two at or above max_hits, as a log2.
int list_log2(int max_hits)
{
    int l = 0;
    while ((1 << l) < max_hits) ++l;
    return l;
}

/// Throws unless `mem` belongs to `context` and holds at least `bytes`.
void check_device_buffer(cl_mem mem, cl_context context, std::uint64_t bytes, const char* what)
{
    if (!mem) throw Error(Error::Kind::InvalidArgument, std::string("ray query: the ") + what + " buffer is null");
    cl_context owner = nullptr;
    std::size_t size = 0;
    if (clGetMemObjectInfo(mem, CL_MEM_CONTEXT, sizeof owner, &owner, nullptr) != CL_SUCCESS ||
        clGetMemObjectInfo(mem, CL_MEM_SIZE, sizeof size, &size, nullptr) != CL_SUCCESS)
        throw Error(Error::Kind::InvalidArgument, std::string("ray query: the ") + what + " buffer is not a valid cl_mem");
    if (owner != context)
        throw Error(Error::Kind::InvalidArgument,
                    std::string("ray query: the ") + what + " buffer belongs to another OpenCL context");
    if (size < bytes)
        throw Error(Error::Kind::InvalidArgument, std::string("ray query: the ") + what + " buffer holds " +
                                                      std::to_string(size) + " bytes, the call needs " +
                                                      std::to_string(bytes));
}

} // namespace

RayQuery::Impl::Impl(Renderer& renderer, const RayQueryOptions& o) : r(RendererAccess::of(renderer, "RayQuery")), options(o)
{
    if (options.batch_rays < 1 || options.batch_rays > (std::size_t(1) << 28))
        throw Error(Error::Kind::InvalidArgument,
                    "ray query: batch_rays must lie in [1, 2^28], got " + std::to_string(options.batch_rays));
    if (options.lanes < 0 || options.lanes > 8)
        throw Error(Error::Kind::InvalidArgument,
                    "ray query: lanes must lie in [0, 8], got " + std::to_string(options.lanes));
    if (!options.brute) error_boundary("preparing the ray queries", [&] { return &r.ray_pipeline_with_bvh(); });
}

RayQuery::Impl::Built& RayQuery::Impl::built_for(RayQueryKind kind)
{
    if (kind != RayQueryKind::All) return built[int(kind)];
    return built_all[list_log2(all.max_hits)][all.counts ? 1 : 0];
}

cl::Kernel& RayQuery::Impl::kernel(RayQueryKind kind)
{
    int entries = options.brute ? 1 : r.ray->stack_entries();
    int stack = (entries / stack_step + 1) * stack_step;
    // brute force on a scene with instances: its items (CLVIS_SCENE_ITEMS), never the expansion
    bool two_level = options.brute ? r.instanced : r.ray->two_level();
    Built& b = built_for(kind);
    if (b.stack != stack || b.two_level != two_level) {
        std::string defs = "-DCLVIS_QUERY=" + std::to_string(int(kind)) + " -DCLVIS_RAY_STACK=" + std::to_string(stack);
        if (kind == RayQueryKind::All) {
            defs += " -DCLVIS_MAX_HITS=" + std::to_string(1 << list_log2(all.max_hits));
            if (all.counts) defs += " -DCLVIS_ALL_COUNTS=1";
        }
        if (!options.brute && r.dev().cpu_hints()) defs += " -DCLVIS_PREFETCH=1";
        if (two_level) defs += options.brute ? " -DCLVIS_SCENE_ITEMS=1" : " -DCLVIS_INSTANCES=1";
        b.lanes = options.brute ? 1 : std::max(1, options.lanes);
        b.per_item = b.lanes > 1 ? std::size_t(items_per_lane * b.lanes) : 1;
        if (!options.brute) defs += " -DCLVIS_QUERY_LANES=" + std::to_string(b.lanes);
        b.kernel = cl::Kernel(r.dev().program("ray_query", defs), options.brute ? "ray_query_brute" : "ray_query");
        std::size_t max_group = b.kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(r.dev().device);
        b.group = std::max<std::size_t>(1, std::min(group_items, max_group));
        // On PoCL's CPU device a work-group's work-items are a loop, and the kernel's private
        // arrays (the walk's stack, the ray) become arrays over the group's work-items, addressed
        // per work-item at every step; a group of one work-item that answers a run of rays keeps
        // them in registers and on the stack (AO rays through the bunny: 5 % less time, the same
        // answers; docs/architecture.md).
        b.runs = !options.brute && b.lanes == 1 && r.dev().cpu_hints();
        if (b.runs) b.group = 1;
        b.stack = stack;
        b.two_level = two_level;
    }
    return b.kernel;
}

void RayQuery::Impl::reserve(std::size_t rays, std::size_t out_per_ray)
{
    // staged_out holds at least capacity hits (the SoA planes of closest hits lie capacity apart)
    std::uint64_t ray_bytes = std::uint64_t(rays) * sizeof(RayRecord);
    std::uint64_t out_bytes = std::uint64_t(std::max(rays, capacity)) * std::max(out_per_ray, sizeof(HitRecord));
    try {
        if (rays > capacity) {
            r.dev().check_allocation(ray_bytes, "a batch of " + std::to_string(rays) + " rays");
            staged_rays = cl::Buffer(r.dev().context, CL_MEM_READ_WRITE, ray_bytes);
            capacity = rays;
        }
        if (out_bytes > staged_out_bytes) {
            r.dev().check_allocation(out_bytes, "the answers of a batch of " + std::to_string(rays) + " rays");
            staged_out = cl::Buffer(r.dev().context, CL_MEM_READ_WRITE, out_bytes);
            staged_out_bytes = out_bytes;
        }
    } catch (const cl::Error& e) {
        throw_cl_error(e, "allocating ray query buffers of " + std::to_string(rays) + " rays");
    }
}

/// One batch: [first, first + m) of `src` into `dst`.
void RayQuery::Impl::batch(RayQueryKind kind, const Source& src, const Sink& dst, std::size_t first, std::size_t m,
                           RayQueryStats& stats)
{
    cl::CommandQueue& q = r.queue;
    cl::Buffer rays = staged_rays, out = staged_out;
    cl_int ray_layout = CLVIS_LAYOUT_AOS, out_layout = CLVIS_LAYOUT_AOS;
    cl_ulong ray_stride = capacity, ray_offset = 0, out_stride = capacity, out_offset = 0;
    const RayInput& in = src.in;
    if (in.on_device) {
        rays = cl::Buffer(in.device.buffer, true);
        ray_layout = in.device.layout == RayLayout::SoA ? CLVIS_LAYOUT_SOA : CLVIS_LAYOUT_AOS;
        ray_stride = src.stride;
        ray_offset = first;
    } else if (!in.soa) {
        q.enqueueWriteBuffer(staged_rays, CL_FALSE, 0, m * sizeof(RayRecord), in.records + first);
    } else {
        const RaySoA& f = in.fields;
        const float* fields[CLVIS_RAY_FIELDS] = {f.ox, f.oy, f.oz, f.tmin, f.dx, f.dy, f.dz, f.tmax};
        for (int k = 0; k < CLVIS_RAY_FIELDS; ++k)
            q.enqueueWriteBuffer(staged_rays, CL_FALSE, k * capacity * 4, m * 4, fields[k] + first);
        ray_layout = CLVIS_LAYOUT_SOA;
    }
    if (dst.device) {
        out = cl::Buffer(dst.device->buffer, true);
        out_layout = dst.device->layout == RayLayout::SoA ? CLVIS_LAYOUT_SOA : CLVIS_LAYOUT_AOS;
        out_stride = dst.stride;
        out_offset = first;
    } else if (dst.soa) {
        out_layout = CLVIS_LAYOUT_SOA;
    }
    const bool direct = invalid_direct() != nullptr; // set by run() where memory is used in place
    if (direct) {
        invalid_word = 0;
    } else {
        cl_uint zero = 0;
        q.enqueueWriteBuffer(invalid, CL_FALSE, 0, sizeof zero, &zero);
    }

    cl::Kernel& k = kernel(kind);
    const Built& built_now = built_for(kind);
    std::size_t group = built_now.group;
    int a = 0;
    std::size_t per_item = 1;
    if (options.brute && built_now.two_level) {
        const InstancedScene& items = r.item_buffers();
        k.setArg(a++, items.positions);
        k.setArg(a++, items.indices);
        k.setArg(a++, cl_uint(items.triangle_count));
        k.setArg(a++, items.meshes);
        k.setArg(a++, items.items);
        k.setArg(a++, cl_uint(items.host_items.size()));
    } else if (options.brute) {
        k.setArg(a++, r.scene_buffers().positions);
        k.setArg(a++, r.scene_buffers().indices);
        k.setArg(a++, cl_uint(r.scene_buffers().triangle_count));
        k.setArg(a++, sizeof(cl_mem), nullptr); // no items (shared/brute_scene.h)
        k.setArg(a++, sizeof(cl_mem), nullptr);
        k.setArg(a++, cl_uint(0));
    } else {
        per_item = built_now.runs ? run_rays(m, r.dev().info.compute_units) : built_now.per_item;
        k.setArg(a++, r.ray->nodes());
        k.setArg(a++, cl_uint(r.ray->node_count()));
        k.setArg(a++, r.ray->triangles());
        if (built_now.two_level) k.setArg(a++, r.ray->instances());
    }
    k.setArg(a++, rays);
    k.setArg(a++, ray_layout);
    k.setArg(a++, ray_stride);
    k.setArg(a++, ray_offset);
    k.setArg(a++, cl_uint(m));
    if (!options.brute) k.setArg(a++, cl_uint(per_item));
    k.setArg(a++, out);
    k.setArg(a++, out_layout);
    k.setArg(a++, out_stride);
    k.setArg(a++, out_offset);
    k.setArg(a++, direct ? invalid_direct : invalid);
    std::size_t per_ray = result_bytes(kind);
    if (kind == RayQueryKind::All) {
        per_ray *= std::size_t(all.max_hits);
        k.setArg(a++, cl_uint(all.max_hits));
        if (all.counts) k.setArg(a++, staged_counts);
        else k.setArg(a++, sizeof(cl_mem), nullptr);
    }
    cl::Event done;
    std::size_t items = (m + per_item - 1) / per_item;
    q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(items, group)), cl::NDRange(group), nullptr, &done);

    if (dst.soa) {
        void* fields[CLVIS_HIT_FIELDS] = {dst.soa->t, dst.soa->id, dst.soa->u, dst.soa->v};
        for (int f = 0; f < CLVIS_HIT_FIELDS; ++f)
            q.enqueueReadBuffer(staged_out, CL_FALSE, f * capacity * 4, m * 4, static_cast<char*>(fields[f]) + first * 4);
    } else if (dst.host) {
        q.enqueueReadBuffer(staged_out, CL_FALSE, 0, m * per_ray, static_cast<char*>(dst.host) + first * per_ray);
    }
    if (kind == RayQueryKind::All && all.counts)
        q.enqueueReadBuffer(staged_counts, CL_FALSE, 0, m * 4, all.counts + first);
    cl_uint bad = 0;
    if (direct) {
        q.finish(); // the kernel and the reads above: the word is the kernel's count now
        bad = *static_cast<volatile cl_uint*>(&invalid_word);
    } else {
        q.enqueueReadBuffer(invalid, CL_TRUE, 0, sizeof bad, &bad);
    }
    stats.invalid += bad;
    stats.batches += 1;
    stats.device_ms += (done.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                        done.getProfilingInfo<CL_PROFILING_COMMAND_START>()) * 1e-6;
}

void RayQuery::Impl::wrap_host(RayQueryKind kind, Source& src, Sink& dst, HostWrap& w)
{
    if (!r.dev().cpu_hints()) return;
    const std::size_t n = src.in.count;
    try {
        if (!src.in.on_device && !src.in.soa) {
            w.rays = cl::Buffer(r.dev().context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, n * sizeof(RayRecord),
                                const_cast<RayRecord*>(src.in.records));
            w.device_rays = DeviceRays{w.rays(), RayLayout::AoS, n, 0};
            src = Source{RayInput(w.device_rays), n};
        } else if (src.in.soa) {
            // the planes back to back in one array of 8 x n floats (NumPy's (8, N)): one buffer
            // over it. Planes merely spaced alike (separate arrays allocated in a row) would bring
            // the memory between them into the buffer: those are staged.
            const RaySoA& f = src.in.fields;
            const float* planes[CLVIS_RAY_FIELDS] = {f.ox, f.oy, f.oz, f.tmin, f.dx, f.dy, f.dz, f.tmax};
            // by address (the planes may be separate arrays: no pointer arithmetic across them)
            auto at = [&](int k) { return reinterpret_cast<std::uintptr_t>(planes[k]); };
            bool packed = true;
            for (int k = 1; k < CLVIS_RAY_FIELDS && packed; ++k) packed = at(k) == at(k - 1) + n * sizeof(float);
            if (packed) {
                w.rays = cl::Buffer(r.dev().context, CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR,
                                    CLVIS_RAY_FIELDS * n * sizeof(float), const_cast<float*>(f.ox));
                w.device_rays = DeviceRays{w.rays(), RayLayout::SoA, n, n};
                src = Source{RayInput(w.device_rays), n};
            }
        }
        if (dst.host && kind != RayQueryKind::All) {
            w.out = cl::Buffer(r.dev().context, CL_MEM_WRITE_ONLY | CL_MEM_USE_HOST_PTR, n * result_bytes(kind), dst.host);
            w.device_out = DeviceResults{w.out(), RayLayout::AoS, 0};
            dst = Sink{};
            dst.device = &w.device_out;
            dst.stride = n;
        }
    } catch (const cl::Error&) {
        // a driver that refuses the caller's memory: the staging buffers, as elsewhere
    }
}

RayQueryStats RayQuery::Impl::run(RayQueryKind kind, const Source& src, const Sink& dst)
{
    auto t0 = std::chrono::steady_clock::now();
    RayQueryStats stats;
    std::size_t n = src.in.count;
    stats.rays = n;
    if (n == 0) return stats;
    error_boundary(std::string("answering a ray query (") + to_string(kind) + ")", [&] {
        if (!options.brute) r.ray_pipeline_with_bvh();
        // all hits: batch_rays hit records per batch at most, so the staging buffers keep their bound
        std::size_t per_batch = options.batch_rays, hits_per_ray = 1;
        if (kind == RayQueryKind::All) {
            hits_per_ray = std::size_t(all.max_hits);
            per_batch = std::max<std::size_t>(1, per_batch / hits_per_ray);
        }
        std::size_t step = std::min(n, per_batch);
        Source in = src;
        Sink out = dst;
        HostWrap wrap; // dst may point into it: it lives as long as the batches
        wrap_host(kind, in, out, wrap);
        const bool direct = r.dev().host_memory_in_place();
        if (direct && !invalid_direct())
            invalid_direct = cl::Buffer(r.dev().context, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR, sizeof(cl_uint),
                                        &invalid_word);
        if (!direct && !invalid()) invalid = cl::Buffer(r.dev().context, CL_MEM_READ_WRITE, sizeof(cl_uint));
        if (!in.in.on_device || !out.device) reserve(step, result_bytes(kind) * hits_per_ray);
        if (kind == RayQueryKind::All && all.counts && step > counts_capacity) {
            staged_counts = cl::Buffer(r.dev().context, CL_MEM_READ_WRITE, step * sizeof(cl_uint));
            counts_capacity = step;
        }
        try {
            for (std::size_t first = 0; first < n; first += step)
                batch(kind, in, out, first, std::min(step, n - first), stats);
        } catch (...) {
            // nothing the queue still holds may touch the caller's arrays once the call is over
            if (wrap.rays() || wrap.out()) {
                try {
                    r.queue.finish();
                } catch (...) {
                }
            }
            throw;
        }
        if (wrap.out() && !direct) {
            // the answers made visible in the caller's array (where the device wrote them: no copy)
            std::size_t bytes = n * result_bytes(kind);
            void* p = r.queue.enqueueMapBuffer(wrap.out, CL_TRUE, CL_MAP_READ, 0, bytes);
            cl::Event unmapped;
            r.queue.enqueueUnmapMemObject(wrap.out, p, nullptr, &unmapped);
            unmapped.wait();
        }
    });
    stats.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return stats;
}

/// Throws when a host array is null while rays are asked for.
static void require(const void* p, std::size_t n, const char* what)
{
    if (n > 0 && !p) throw Error(Error::Kind::InvalidArgument, std::string("ray query: ") + what + " is null");
}

RayQuery::Impl::Source RayQuery::Impl::source(const RayInput& in)
{
    Source s{in};
    if (!in.on_device && !in.soa) require(in.records, in.count, "the ray array");
    if (in.soa) {
        const RaySoA& f = in.fields;
        for (const float* p : {f.ox, f.oy, f.oz, f.tmin, f.dx, f.dy, f.dz, f.tmax}) require(p, in.count, "a ray field array");
    }
    if (!in.on_device) return s;
    const DeviceRays& rays = in.device;
    s.stride = rays.stride ? rays.stride : rays.count;
    if (rays.layout == RayLayout::SoA && s.stride < rays.count)
        throw Error(Error::Kind::InvalidArgument, "ray query: SoA stride " + std::to_string(rays.stride) +
                                                      " is below the ray count " + std::to_string(rays.count));
    std::uint64_t bytes = rays.layout == RayLayout::AoS ? std::uint64_t(rays.count) * sizeof(RayRecord)
                                                        : (std::uint64_t(7) * s.stride + rays.count) * 4;
    if (rays.count > 0) check_device_buffer(rays.buffer, r.dev().context(), bytes, "rays");
    return s;
}

RayQuery::Impl::Sink RayQuery::Impl::device_sink(RayQueryKind kind, const DeviceResults& out, std::size_t n)
{
    Sink s;
    s.device = &out;
    bool soa = kind == RayQueryKind::Closest && out.layout == RayLayout::SoA;
    s.stride = out.stride ? out.stride : n;
    if (soa && s.stride < n)
        throw Error(Error::Kind::InvalidArgument, "ray query: SoA stride " + std::to_string(out.stride) +
                                                      " of the hits is below the ray count " + std::to_string(n));
    std::uint64_t bytes = soa ? (std::uint64_t(3) * s.stride + n) * 4 : std::uint64_t(n) * result_bytes(kind);
    if (n > 0) check_device_buffer(out.buffer, r.dev().context(), bytes, "results");
    return s;
}

RayQuery::Impl::Sink RayQuery::Impl::host_sink(void* out, std::size_t n)
{
    require(out, n, "the result array");
    Sink s;
    s.host = out;
    return s;
}

RayQuery::RayQuery(Renderer& renderer, RayQueryOptions options) : impl_(std::make_unique<Impl>(renderer, options)) {}
RayQuery::~RayQuery() = default;
RayQuery::RayQuery(RayQuery&&) noexcept = default;
RayQuery& RayQuery::operator=(RayQuery&&) noexcept = default;
const RayQueryOptions& RayQuery::options() const { return impl_->options; }

RayQueryStats RayQuery::closest(const RayInput& rays, HitRecord* hits)
{
    return impl_->run(RayQueryKind::Closest, impl_->source(rays), impl_->host_sink(hits, rays.count));
}

RayQueryStats RayQuery::closest(const RayInput& rays, const HitSoA& hits)
{
    for (const void* f : {static_cast<const void*>(hits.t), static_cast<const void*>(hits.id),
                          static_cast<const void*>(hits.u), static_cast<const void*>(hits.v)})
        require(f, rays.count, "a hit field array");
    Impl::Sink s;
    s.soa = &hits;
    return impl_->run(RayQueryKind::Closest, impl_->source(rays), s);
}

RayQueryStats RayQuery::closest(const RayInput& rays, const DeviceResults& hits)
{
    return impl_->run(RayQueryKind::Closest, impl_->source(rays), impl_->device_sink(RayQueryKind::Closest, hits, rays.count));
}

RayQueryStats RayQuery::occluded(const RayInput& rays, std::uint8_t* flags)
{
    return impl_->run(RayQueryKind::Any, impl_->source(rays), impl_->host_sink(flags, rays.count));
}

RayQueryStats RayQuery::occluded(const RayInput& rays, const DeviceResults& flags)
{
    return impl_->run(RayQueryKind::Any, impl_->source(rays), impl_->device_sink(RayQueryKind::Any, flags, rays.count));
}

RayQueryStats RayQuery::count(const RayInput& rays, std::uint32_t* counts)
{
    return impl_->run(RayQueryKind::Count, impl_->source(rays), impl_->host_sink(counts, rays.count));
}

RayQueryStats RayQuery::count(const RayInput& rays, const DeviceResults& counts)
{
    return impl_->run(RayQueryKind::Count, impl_->source(rays), impl_->device_sink(RayQueryKind::Count, counts, rays.count));
}

RayQueryStats RayQuery::all(const RayInput& rays, int max_hits, HitRecord* hits, std::uint32_t* counts)
{
    if (max_hits < 1 || max_hits > ray_query_max_hits)
        throw Error(Error::Kind::InvalidArgument, "ray query: max_hits must lie in [1, " +
                                                      std::to_string(ray_query_max_hits) + "], got " +
                                                      std::to_string(max_hits));
    if (counts) require(counts, rays.count, "the count array");
    Impl::Source src = impl_->source(rays);
    Impl::Sink dst = impl_->host_sink(hits, rays.count);
    impl_->all = Impl::AllRequest{max_hits, counts};
    return impl_->run(RayQueryKind::All, src, dst);
}

} // namespace clvis
