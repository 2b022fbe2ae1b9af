// The ray path: builds the BVH on the host (bvh_build.cpp), keeps it resident on the device,
// follows moved vertices by refit or rebuild, and enqueues one trace per frame: through the BVH by
// RenderOptions::ray_mapping (ray_trace.cl, a work-item per 4x4 packet; ray_trace_single.cl, a
// work-item per pixel and a work-group per tile: the same keys), or ray_brute.cl against every
// triangle, each built for RenderOptions::coverage (the watertight test, or CLVIS_RASTER_RULE: the
// raster path's predicate).
#include "ray/ray_pipeline.hpp"

#include "frame/instanced_scene.hpp"
#include "ray/bvh_build.hpp"
#include "ray/bvh_instances.hpp"
#include "runtime/cl_runtime.hpp"

#include "shared/ray.h"

#include <array>
#include <chrono>
#include <string>

namespace clvis::detail {

static_assert(sizeof(clvis_bvh_node) == 32, "layout shared with kernels/shared/bvh.h");
static_assert(sizeof(clvis_wide_node) == 32 * bvh_width, "layout shared with kernels/shared/bvh.h");
static_assert(sizeof(clvis_bvh_tri) == 40, "layout shared with kernels/shared/bvh.h");
static_assert(sizeof(clvis_instance) == 56, "layout shared with kernels/shared/instance.h");

namespace {

/// Pixels per work-item of ray_trace.cl: a packet of 16 rays.
constexpr std::size_t packet_w = CLVIS_PACKET_W, packet_h = CLVIS_PACKET_H;
/// The traversal stack grows in steps of this many entries (each step is one program build).
constexpr int stack_step = 16;

/// Work-groups (in work-items) in order of preference; the first the kernel and device allow wins.
/// On PoCL a group of 4x4 packets (16x16 pixels) ran as fast as smaller ones and faster than 8x8
/// (whose private stacks and packets no longer stay in cache).
constexpr std::array<std::array<std::size_t, 2>, 5> group_choices{{{4, 4}, {4, 2}, {2, 2}, {2, 1}, {1, 1}}};

/// Rays per work-group of ray_trace_single.cl that the tile aims at (two 32-wide SIMD groups), or
/// the kernel's preferred multiple where larger; the kernel's grant and the device's item sizes
/// cap it.
constexpr std::size_t single_group_items = 64;

/// Leaf triangles gathered per write of the flat tree's upload (2.5 MB of host staging).
constexpr std::size_t tri_block = std::size_t(1) << 16;

/// The build option that selects the coverage mode of ray_trace.cl and ray_brute.cl.
std::string coverage_define(Coverage coverage)
{
    return coverage == Coverage::RasterRule ? "-DCLVIS_RASTER_RULE=1" : "";
}

/// The build option of depth layers (RenderOptions::layers): none for one layer, so that a
/// one-layer build is the kernels' own.
std::string layers_define(int layers)
{
    return layers > 1 ? "-DCLVIS_LAYERS=" + std::to_string(layers) : "";
}

/// Joins build options, skipping empty ones.
std::string join_defines(std::string a, const std::string& b)
{
    if (b.empty()) return a;
    return a.empty() ? b : a + " " + b;
}

double ms_since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

} // namespace

struct RayPipeline::Impl {
    Device::Impl& device;
    RenderOptions options;
    bool single; ///< RayMapping::Single: ray_trace_single.cl, a work-item per pixel (Auto: packets until set_mapping)
    cl::Kernel trace, trace_views, brute;
    cl::NDRange trace_group, views_group, brute_group; ///< work-items per work-group
    cl::Kernel brute_items;         ///< ray_brute.cl with CLVIS_SCENE_ITEMS, made on first use
    cl::NDRange brute_items_group;
    int trace_stack = 0;                  ///< CLVIS_RAY_STACK of the built trace kernel
    /// The binary tree, kept for refits (flat: a scene without instances). Between builds and
    /// refits the host holds one byte a node of it (issue 37's memory): `shape`, each node's leaf
    /// count (bvh_leaf_counts), from which a refit derives every first and count again; the leaf
    /// slots' ids are read back from the device's triangles, and `leaf_slots` is their number.
    Bvh bvh;
    std::vector<std::uint8_t> shape;
    std::size_t leaf_slots = 0;
    /// What the kernel reads; its nodes and source are freed on the host once uploaded (a refit
    /// reads the nodes back and derives the source: wide_source_of), its depth kept. wide_nodes:
    /// their count.
    BvhWide wide;
    std::size_t wide_nodes = 0;
    bool built = false;
    cl::Buffer nodes, tris;
    BvhStats stats;
    /// A scene with instances: the two-level BVH (bvh_instances.hpp) in levels_*, read by the
    /// trace and the ray queries alike (no flat tree of the expansion is built).
    bool two_level = false;
    InstanceBvh levels;
    cl::Buffer level_nodes, level_tris, instances;

    Impl(Device::Impl& d, const RenderOptions& o) : device(d), options(o), single(o.ray_mapping == RayMapping::Single)
    {
    }

    /// The first preferred work-group that `kernel` may run: what CL_KERNEL_WORK_GROUP_SIZE grants.
    cl::NDRange pick_group(const cl::Kernel& kernel) const
    {
        std::size_t max_group = kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device.device);
        auto item_sizes = device.device.getInfo<CL_DEVICE_MAX_WORK_ITEM_SIZES>();
        for (auto g : group_choices) {
            if (g[0] * g[1] <= max_group && g[0] <= item_sizes.at(0) && g[1] <= item_sizes.at(1))
                return cl::NDRange(g[0], g[1]);
        }
        throw Error(Error::Kind::Limit, "the ray kernels cannot run on " + device.info.name +
                                            " (work-group size " + std::to_string(max_group) + ")");
    }

    /// The tile of pixels a work-group of ray_trace_single.cl traces: single_group_items rays (or
    /// the kernel's preferred multiple), within what CL_KERNEL_WORK_GROUP_SIZE grants and the
    /// device's item sizes allow, grown in powers of two, x first, as square as they allow.
    cl::NDRange pick_tile(const cl::Kernel& kernel) const
    {
        std::size_t grant = kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device.device);
        std::size_t multiple = kernel.getWorkGroupInfo<CL_KERNEL_PREFERRED_WORK_GROUP_SIZE_MULTIPLE>(device.device);
        auto item_sizes = device.device.getInfo<CL_DEVICE_MAX_WORK_ITEM_SIZES>();
        std::size_t items = std::min(grant, std::max(single_group_items, multiple)), gx = 1, gy = 1;
        while (gx * gy * 2 <= items) {
            bool wider = gx * 2 <= item_sizes.at(0), taller = gy * 2 <= item_sizes.at(1);
            if (wider && (gx <= gy || !taller)) gx *= 2;
            else if (taller) gy *= 2;
            else break;
        }
        return cl::NDRange(gx, gy);
    }

    /// The work-items of a trace launch along x and y for `width` x `height` pixels: a pixel
    /// each (single) or a packet each, rounded up to whole groups of `g`.
    cl::NDRange trace_items(int width, int height, const cl::NDRange& g) const
    {
        std::size_t pw = single ? 1 : packet_w, ph = single ? 1 : packet_h;
        return cl::NDRange(round_up((std::size_t(width) + pw - 1) / pw, g[0]),
                           round_up((std::size_t(height) + ph - 1) / ph, g[1]));
    }

    /// The trace kernel with a stack for the tree's depth: each wide node on the current path
    /// leaves at most bvh_width - 1 children on it.
    void prepare_trace()
    {
        int entries = two_level ? levels.stack_entries() : (bvh_width - 1) * wide.depth + 1;
        int stack = (entries / stack_step + 1) * stack_step;
        if (stack == trace_stack) return;
        if (options.layers > 1 && !single && device.loop_limit() != Device::Impl::loop_unlimited)
            throw Error(Error::Kind::InvalidArgument,
                        "layers " + std::to_string(options.layers) + " with ray mapping 'packet' on " + device.info.name +
                            ", which caps a work-item's loops: its 16 lanes' layers could pass the cap; use ray "
                            "mapping 'single' or 'auto'");
        std::string define = join_defines(coverage_define(options.coverage), layers_define(options.layers));
        std::string name = single ? "ray_trace_single" : "ray_trace";
        if (!single && device.cpu_hints()) define += " -DCLVIS_PREFETCH=1 -DCLVIS_REDUCE_OR=1";
        cl::Program program = device.program(name, "-DCLVIS_RAY_STACK=" + std::to_string(stack) +
                                                       (define.empty() ? "" : " " + define));
        trace = cl::Kernel(program, name.c_str());
        trace_views = cl::Kernel(program, (name + "_views").c_str());
        trace_group = single ? pick_tile(trace) : pick_group(trace);
        views_group = single ? pick_tile(trace_views) : pick_group(trace_views);
        trace_stack = stack;
    }

    /// The trace kernels' tree arguments: 1-3 (nodes, node count, triangles), 7-8 (instances,
    /// two_level).
    void set_tree_args(cl::Kernel& k)
    {
        k.setArg(1, two_level ? level_nodes : nodes);
        k.setArg(2, cl_uint(two_level ? levels.nodes().size() : wide_nodes));
        k.setArg(3, two_level ? level_tris : tris);
        k.setArg(7, instances);
        k.setArg(8, cl_int(two_level));
    }

    /// Writes `items` into `buffer` (made or remade at their size, at least one element).
    template <typename T>
    void put(cl::Buffer& buffer, const std::vector<T>& items, const std::string& what, cl::CommandQueue& queue)
    {
        std::uint64_t bytes = std::max<std::uint64_t>(items.size(), 1) * sizeof(T);
        device.check_allocation(bytes, "the BVH's " + std::to_string(items.size()) + " " + what);
        if (!buffer() || buffer.getInfo<CL_MEM_SIZE>() != bytes)
            buffer = cl::Buffer(device.context, CL_MEM_READ_ONLY, bytes);
        if (!items.empty()) queue.enqueueWriteBuffer(buffer, CL_FALSE, 0, items.size() * sizeof(T), items.data());
    }

    static void check_nodes(std::size_t count)
    {
        // (2^29 - 1 at width 8): a stack entry names node << CLVIS_BVH_SLOT_BITS | slot, one of
        // all ones enters an instance, and a root's top bit marks the plain meshes' entry
        // (shared/instance.h)
        constexpr int node_bits = 32 - CLVIS_BVH_SLOT_BITS;
        if (count >= (std::size_t(1) << node_bits) - 1)
            throw Error(Error::Kind::Limit, "the BVH's " + std::to_string(count) + " nodes exceed the ray kernel's 2^" +
                                                std::to_string(node_bits) + " - 1");
    }

    /// Gathers the leaf triangles of bvh.ids from `world` straight into `tris`, a block at a time:
    /// no host copy of all of them (40 bytes a triangle) beside the device's.
    void put_tris(const WorldMesh& world, cl::CommandQueue& queue)
    {
        const std::vector<std::uint32_t>& ids = bvh.ids;
        std::uint64_t bytes = std::max<std::uint64_t>(ids.size(), 1) * sizeof(clvis_bvh_tri);
        device.check_allocation(bytes, "the BVH's " + std::to_string(ids.size()) + " triangles");
        if (!tris() || tris.getInfo<CL_MEM_SIZE>() != bytes) tris = cl::Buffer(device.context, CL_MEM_READ_ONLY, bytes);
        std::vector<clvis_bvh_tri> block(std::min(ids.size(), tri_block));
        for (std::size_t at = 0; at < ids.size(); at += tri_block) {
            std::size_t n = std::min(tri_block, ids.size() - at);
            gather_bvh_tris(world.positions, world.indices, ids.data() + at, n, block.data());
            queue.enqueueWriteBuffer(tris, CL_TRUE, at * sizeof(clvis_bvh_tri), n * sizeof(clvis_bvh_tri), block.data());
        }
    }

    /// Keeps of the binary nodes only what a refit reads (the shape: it recomputes every box and
    /// derives first and count from the leaf counts): a byte a node, not 32, before the upload.
    void compact_binary()
    {
        shape = bvh_leaf_counts(bvh.nodes);
        std::vector<clvis_bvh_node>().swap(bvh.nodes);
    }

    /// Once the wide nodes are on the device: frees the host's and their source, which only a
    /// refit reads again (restore_host_tree).
    void release_host_tree()
    {
        wide_nodes = wide.nodes.size();
        std::vector<clvis_wide_node>().swap(wide.nodes);
        std::vector<std::uint32_t>().swap(wide.source);
    }

    /// The host tree release_host_tree freed, for a refit: binary nodes from the shape (boxes
    /// zero: a refit recomputes every one), the leaf slots and wide nodes read back from the
    /// device (a refit reads the slots' ids and writes their vertices), the source derived.
    void restore_host_tree(cl::CommandQueue& queue)
    {
        bvh.nodes = bvh_from_leaf_counts(shape);
        bvh.tris.resize(leaf_slots);
        wide.nodes.resize(wide_nodes);
        try {
            if (leaf_slots) queue.enqueueReadBuffer(tris, CL_TRUE, 0, leaf_slots * sizeof(clvis_bvh_tri), bvh.tris.data());
            if (wide_nodes) queue.enqueueReadBuffer(nodes, CL_TRUE, 0, wide_nodes * sizeof(clvis_wide_node), wide.nodes.data());
        } catch (const cl::Error& e) {
            throw_cl_error(e, "reading the BVH back from " + device.info.name);
        }
        wide.source = wide_source_of(bvh.nodes, wide.nodes);
    }

    /// Uploads the flat BVH (nodes, tris: gathered from `world` where given, else bvh.tris), or
    /// with `levels_too` the two-level one.
    void upload(cl::CommandQueue& queue, bool levels_too, const WorldMesh* world = nullptr)
    {
        auto t0 = std::chrono::steady_clock::now();
        try {
            if (levels_too) {
                check_nodes(levels.nodes().size());
                put(level_nodes, levels.nodes(), "nodes", queue);
                put(level_tris, levels.tris(), "triangles", queue);
                put(instances, levels.instances(), "instances", queue);
            } else {
                // One large piece on the host at a time beside the device's: the binary boxes
                // dropped, the wide nodes uploaded and freed, then the leaf triangles gathered.
                check_nodes(wide.nodes.size());
                compact_binary();
                put(nodes, wide.nodes, "nodes", queue);
                queue.finish();
                release_host_tree();
                if (world) put_tris(*world, queue);
                else put(tris, bvh.tris, "triangles", queue);
                // A refit reads the ids back from the device's slots (restore_host_tree).
                leaf_slots = world ? bvh.ids.size() : bvh.tris.size();
                std::vector<std::uint32_t>().swap(bvh.ids);
                if (!instances()) put(instances, std::vector<clvis_instance>(), "instances", queue);
            }
            queue.finish();
            if (!levels_too) std::vector<clvis_bvh_tri>().swap(bvh.tris);
        } catch (const cl::Error& e) {
            throw_cl_error(e, "uploading the BVH to " + device.info.name);
        }
        stats.upload_ms = ms_since(t0);
        stats.device_bytes = 0;
        for (const cl::Buffer* b : {&nodes, &tris, &level_nodes, &level_tris, &instances})
            if ((*b)()) stats.device_bytes += b->getInfo<CL_MEM_SIZE>();
    }

    void fill_stats(double build_ms, bool refitted)
    {
        stats.build_ms = build_ms;
        stats.nodes = two_level ? levels.binary_nodes() : bvh.nodes.size();
        stats.leaves = two_level ? levels.leaves() : bvh.leaves;
        stats.depth = two_level ? levels.depth() : bvh.depth;
        stats.sah_cost = two_level ? 0.0 : bvh.sah_cost;
        stats.refitted = refitted;
        stats.instances = two_level ? levels.instances().size() : 0;
        stats.prototype_builds = levels.prototype_builds();
        stats.top_build_ms = two_level ? levels.top_ms() : 0.0;
    }

    BvhBuildOptions build_options() const
    {
        BvhBuildOptions o;
        static_cast<BvhOptions&>(o) = options.bvh;
        return o;
    }

    /// Builds the flat tree of `world` without gathering its leaf triangles (upload gathers them).
    void build_flat(const Scene& scene, const WorldMesh& world)
    {
        BvhBuildOptions o = build_options();
        o.gather = false;
        bvh = build_bvh(world.positions, world.indices, scene.triangle_count(), o, &wide);
    }

    /// Builds everything `scene` needs: the flat BVH, or the two levels (prototype trees reused).
    void rebuild(const Scene& scene, cl::CommandQueue& queue)
    {
        auto t0 = std::chrono::steady_clock::now();
        two_level = false;
        for (const Scene::Mesh& m : scene.meshes()) two_level |= m.prototype != Scene::no_prototype;
        if (two_level) {
            levels.update(scene, build_options());
            fill_stats(ms_since(t0), levels.plain_refitted());
            prepare_trace();
            upload(queue, true);
        } else {
            // The world positions for this build and upload only (the mesh's own where it is one
            // untransformed mesh), not the Scene's cached expansion.
            WorldMesh world = world_mesh(scene);
            build_flat(scene, world);
            fill_stats(ms_since(t0), false); // the upload is timed on its own (upload_ms)
            prepare_trace();
            upload(queue, false, &world);
        }
        built = true;
    }

    /// Enqueues the trace of frame.gpu_camera.sample of every pixel.
    void render_sample(const DeviceScene& scene, Frame& frame, bool brute);
};

RayPipeline::RayPipeline(Device::Impl& device, const RenderOptions& options)
    : impl_(std::make_unique<Impl>(device, options))
{
    impl_->brute = cl::Kernel(device.program("ray_brute", join_defines(coverage_define(options.coverage), layers_define(options.layers))), "ray_brute");
    impl_->brute_group = impl_->pick_group(impl_->brute);
}

RayPipeline::~RayPipeline() = default;

void RayPipeline::build(const Scene& scene, cl::CommandQueue& queue) { impl_->rebuild(scene, queue); }

void RayPipeline::set_mapping(RayMapping mapping)
{
    Impl& m = *impl_;
    bool single = mapping == RayMapping::Single;
    if (single == m.single) return;
    m.single = single;
    m.trace_stack = 0; // the other kernel: built again, now if the tree is there
    if (m.built) m.prepare_trace();
}

void RayPipeline::update(const Scene& scene, cl::CommandQueue& queue)
{
    Impl& m = *impl_;
    if (!m.built || m.two_level || m.options.bvh.update == BvhUpdate::Rebuild ||
        m.leaf_slots != scene.triangle_count()) {
        m.rebuild(scene, queue);
        return;
    }
    auto t0 = std::chrono::steady_clock::now();
    WorldMesh world = world_mesh(scene);
    m.restore_host_tree(queue);
    refit_bvh(m.bvh, world.positions, world.indices);
    refit_wide(m.wide, m.bvh);
    m.fill_stats(ms_since(t0), true);
    m.upload(queue, false);
}

bool RayPipeline::built() const { return impl_->built; }

const BvhStats& RayPipeline::stats() const { return impl_->stats; }
const cl::Buffer& RayPipeline::nodes() const { return impl_->two_level ? impl_->level_nodes : impl_->nodes; }
const cl::Buffer& RayPipeline::triangles() const { return impl_->two_level ? impl_->level_tris : impl_->tris; }
std::uint32_t RayPipeline::node_count() const
{
    return std::uint32_t(impl_->two_level ? impl_->levels.nodes().size() : impl_->wide_nodes);
}
const cl::Buffer& RayPipeline::instances() const { return impl_->instances; }
bool RayPipeline::two_level() const { return impl_->two_level; }
int RayPipeline::stack_entries() const { return impl_->two_level ? impl_->levels.stack_entries() : (bvh_width - 1) * impl_->wide.depth + 1; }

void RayPipeline::render(const DeviceScene& scene, Frame& frame, bool brute)
{
    // One launch per sample (shared/samples.h): each lane's ray goes through its pixel's sample.
    for (int sample = 0; sample < 1 << frame.gpu_camera.sample_log2; ++sample) {
        frame.gpu_camera.sample = sample;
        impl_->render_sample(scene, frame, brute);
    }
    frame.gpu_camera.sample = 0;
}

void RayPipeline::Impl::render_sample(const DeviceScene& scene, Frame& frame, bool brute)
{
    Impl& m = *this;
    cl::Event done;
    if (brute) {
        cl::Kernel& k = m.brute;
        const cl::NDRange& g = m.brute_group;
        k.setArg(0, sizeof frame.gpu_camera, &frame.gpu_camera);
        k.setArg(1, scene.positions);
        k.setArg(2, scene.indices);
        k.setArg(3, cl_uint(scene.triangle_count));
        k.setArg(4, cl_int(cull_mode(m.options.cull)));
        k.setArg(5, frame.keys);
        k.setArg(6, sizeof frame.region, &frame.region);
        k.setArg(7, sizeof(cl_mem), nullptr); // no items: the expansion's arrays (shared/brute_scene.h)
        k.setArg(8, sizeof(cl_mem), nullptr);
        k.setArg(9, cl_uint(0));
        cl::NDRange global(round_up(std::size_t(frame.width), g[0]), round_up(std::size_t(frame.height), g[1]));
        frame.queue.enqueueNDRangeKernel(k, cl::NullRange, global, g, nullptr, &done);
    } else {
        if (!m.built) throw Error(Error::Kind::InvalidArgument, "the ray path renders before its BVH is built");
        cl::Kernel& k = m.trace;
        const cl::NDRange& g = m.trace_group;
        k.setArg(0, sizeof frame.gpu_camera, &frame.gpu_camera);
        m.set_tree_args(k);
        k.setArg(4, cl_int(cull_mode(m.options.cull)));
        k.setArg(5, frame.keys);
        k.setArg(6, sizeof frame.region, &frame.region);
        frame.queue.enqueueNDRangeKernel(k, cl::NullRange, m.trace_items(frame.width, frame.height, g), g, nullptr,
                                         &done);
    }
    frame.stages->add("trace", done);
}

void RayPipeline::render_brute(const InstancedScene& scene, Frame& frame)
{
    Impl& m = *impl_;
    if (!m.brute_items()) {
        std::string defines =
            join_defines(join_defines(coverage_define(m.options.coverage), layers_define(m.options.layers)),
                         "-DCLVIS_SCENE_ITEMS=1");
        m.brute_items = cl::Kernel(m.device.program("ray_brute", defines), "ray_brute");
        m.brute_items_group = m.pick_group(m.brute_items);
    }
    cl::Kernel& k = m.brute_items;
    const cl::NDRange& g = m.brute_items_group;
    k.setArg(1, scene.positions);
    k.setArg(2, scene.indices);
    k.setArg(3, cl_uint(scene.triangle_count));
    k.setArg(4, cl_int(cull_mode(m.options.cull)));
    k.setArg(5, frame.keys);
    k.setArg(6, sizeof frame.region, &frame.region);
    k.setArg(7, scene.meshes);
    k.setArg(8, scene.items);
    k.setArg(9, cl_uint(scene.host_items.size()));
    cl::NDRange global(round_up(std::size_t(frame.width), g[0]), round_up(std::size_t(frame.height), g[1]));
    // One launch per sample, as render's.
    for (int sample = 0; sample < 1 << frame.gpu_camera.sample_log2; ++sample) {
        frame.gpu_camera.sample = sample;
        k.setArg(0, sizeof frame.gpu_camera, &frame.gpu_camera);
        cl::Event done;
        frame.queue.enqueueNDRangeKernel(k, cl::NullRange, global, g, nullptr, &done);
        frame.stages->add("trace", done);
    }
    frame.gpu_camera.sample = 0;
}

void RayPipeline::render_views(ViewsFrame& frame)
{
    Impl& m = *impl_;
    if (!m.built) throw Error(Error::Kind::InvalidArgument, "the ray path renders before its BVH is built");
    cl::Kernel& k = m.trace_views;
    const cl::NDRange& g = m.views_group;
    k.setArg(0, frame.cameras);
    m.set_tree_args(k);
    k.setArg(4, cl_int(cull_mode(m.options.cull)));
    k.setArg(5, frame.keys);
    k.setArg(6, cl_ulong(frame.stride));
    cl::NDRange items = m.trace_items(frame.width, frame.height, g);
    cl::NDRange global(items[0], items[1], std::size_t(frame.views));
    cl::Event done;
    frame.queue.enqueueNDRangeKernel(k, cl::NullRange, global, cl::NDRange(g[0], g[1], 1), nullptr, &done);
    frame.stages->add("trace", done);
}

} // namespace clvis::detail
