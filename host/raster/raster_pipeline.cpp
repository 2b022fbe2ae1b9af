// The raster path: raster_setup.cl projects and clips every triangle, rasterizes the small ones
// at once (64-bit atomic min) and lists the others; raster_bin.cl bins those into tiles (count,
// scan, fill); raster_fine.cl rasterizes each tile's bin. Under tile ownership (RasterAtomics::Off,
// or Auto on a device without 64-bit atomics) setup lists every triangle and raster_fine.cl writes
// every key once (the background too), with no clear and no atomics on the keys. On a device that
// caps a work-item's loop iterations (Device::Impl::loop_limit), raster_fine.cl walks long bins in
// several launches. RasterMapping::Pixel runs raster_fine_pixel instead (a work-group per square
// of a tile, a work-item per pixel, the bin walked in batches through local memory). The list and
// bins keep their capacities from frame to frame; the bin kernels read the listed count on the
// device, the host reads the counts back once, after raster_fine.cl (which writes nothing for a
// bin past the capacity), and grows what overflowed and draws the sample again rather than drop.
// A scene with instances is drawn without its expansion, in chunks of whole items
// (render/instanced_scene.hpp): per chunk raster_setup_item_vertices and raster_setup_items, then
// the stages above, every chunk's keys merged into the same buffer.
#include "render/pipeline.hpp"

#include "render/instanced_scene.hpp"
#include "render/renderer_probe.hpp"
#include "runtime/cl_runtime.hpp"

#include "shared/raster.h"

#include <clvis/error.hpp>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace clvis::detail {

static_assert(sizeof(clvis_raster_tri) == 112, "layout shared with kernels/shared/raster.h");
static_assert(sizeof(clvis_raster_projected) == 16, "layout shared with kernels/shared/raster.h");
static_assert(sizeof(clvis_camera_gpu) == 96, "layout shared with kernels/shared/camera.h");

// The raster-space limits derived in kernels/shared/raster.h, checked where the kernels get them.
static_assert(CLVIS_GUARD_MARGIN >= 8, "the 8-pixel spans of raster_fine.cl stay inside the guard band");
static_assert(((std::int64_t(CLVIS_MAX_IMAGE_SIZE) + CLVIS_GUARD_MARGIN + CLVIS_GUARD_SLACK)
               << CLVIS_SUBPIXEL_BITS) < (std::int64_t(1) << 31),
              "int32 16.16 holds every snapped raster coordinate");
static_assert(std::uint64_t(CLVIS_RASTER_SPAN) * std::uint64_t(CLVIS_RASTER_SPAN) <
                  (std::uint64_t(1) << (63 - 2 * CLVIS_SUBPIXEL_BITS)),
              "int64 holds every edge-function value (L^2 2^2F < 2^63)");

namespace {

/// Tile edge in pixels when RenderOptions::tile_size is 0 (log2), measured on PoCL (2 cores).
constexpr int default_tile_log2 = 4;
/// Work-items per group of the one-dimensional kernels (setup, bin count and fill), at most.
constexpr std::size_t linear_group = 64;
/// Lists of binned triangles up to this capacity are binned by work-groups of small_bin_group.
/// The suzanne close-up of the benchmark: binning 0.8 -> 0.5 ms (PoCL, 2 cores); 16 gained nothing.
constexpr std::size_t small_bin_list = std::size_t(1) << 14, small_bin_group = 4;
/// Work-items per group edge of raster_fine.cl (each owns a square of pixels), at most.
constexpr std::size_t fine_group_edge = 4;
/// Pixels per group edge of raster_fine_pixel, at most (fewer where the grant, local memory or tile ask).
constexpr std::size_t pixel_group_edge = 16;
/// Work-items of the single work-group of raster_bin_scan, at most.
constexpr std::size_t scan_group = 256;
/// First capacities of the growable buffers (elements); they double or jump to what a frame needs.
constexpr std::size_t first_tri_capacity = raster_first_tri_capacity, first_entry_capacity = std::size_t(1) << 14;
/// The probe's first capacities (set_raster_first_capacities; 0: the defaults above).
std::atomic<std::size_t> probe_tri_capacity{0}, probe_entry_capacity{0};

/// The counts read back once a sample: triangles listed, bin entries in all, the longest bin's.
struct RasterCounts { cl_ulong listed, entries, longest; };

std::size_t floor_pow2(std::size_t v)
{
    std::size_t p = 1;
    while (p * 2 <= v) p *= 2;
    return p;
}

} // namespace

int raster_tile_log2(const RenderOptions& options)
{
    if (options.tile_size == 0) return default_tile_log2;
    int log2 = 0;
    while ((1 << log2) < options.tile_size) ++log2;
    return log2;
}

bool raster_owned(const DeviceInfo& info, const RenderOptions& options)
{
    return options.raster_atomics == RasterAtomics::Off ||
           (options.raster_atomics == RasterAtomics::Auto && !info.int64_atomics);
}

struct RasterPipeline::Impl {
    Device::Impl& device;
    int tile_log2;
    int cull = CLVIS_CULL_NONE;
    bool owned = false; ///< tile ownership: raster_setup.cl built with CLVIS_RASTER_OWNED
    bool pixel = false; ///< RasterMapping::Pixel: raster_fine_pixel
    std::uint32_t loop_limit = Device::Impl::loop_unlimited; ///< the device's, measured
    std::uint32_t fine_chunk = 0xFFFFFFFFu; ///< bin entries per launch of raster_fine.cl
    cl::Kernel clear, zero, vertices, setup, bin_count, bin_scan, bin_fill, fine;
    cl::Kernel item_vertices, item_setup; ///< the same two stages for a chunk of items
    std::size_t zero_group = 1, vertex_group = 1, setup_group = 1, bin_group = 1, scan_items = 1;
    cl::NDRange fine_group;
    cl::Buffer counters; ///< uint[2] triangles listed by setup (low, high word), ulong bin entries, ulong longest bin
    cl::Buffer projected, tris, entries, tile_counts, offsets, cursors;
    std::size_t projected_capacity = 0, tri_capacity = 0, entry_capacity = 0, tile_capacity = 0;
    bool counts_zero = true; ///< tile_counts all zero (raster_bin_scan zeroes them once read)

    Impl(Device::Impl& d, const RenderOptions& o)
        : device(d), tile_log2(raster_tile_log2(o)), cull(cull_mode(o.cull)), owned(raster_owned(d.info, o)),
          pixel(o.raster_mapping == RasterMapping::Pixel)
    {
    }

    /// Edge in pixels of the square a work-item of raster_fine.cl owns.
    std::size_t fine_square() const { return std::min<std::size_t>(std::size_t(1) << tile_log2, CLVIS_FINE_SUB); }

    std::size_t granted(const cl::Kernel& k) const
    {
        return k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device.device);
    }

    void pick_groups()
    {
        zero_group = std::min(linear_group, floor_pow2(granted(zero)));
        vertex_group = std::min({linear_group, floor_pow2(granted(vertices)), floor_pow2(granted(item_vertices))});
        setup_group = std::min({linear_group, floor_pow2(granted(setup)), floor_pow2(granted(item_setup))});
        bin_group = std::min({linear_group, floor_pow2(granted(bin_count)), floor_pow2(granted(bin_fill))});
        scan_items = std::min(scan_group, floor_pow2(granted(bin_scan)));
        auto item_sizes = device.device.getInfo<CL_DEVICE_MAX_WORK_ITEM_SIZES>();
        std::size_t max_group = floor_pow2(granted(fine));
        if (pixel) {
            // raster_fine_pixel: a square group of pixels that divides the tile, within the
            // kernel's grant, the item sizes, and half the local memory (a triangle per item).
            std::size_t local = device.device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
            std::size_t items = std::min(max_group, floor_pow2(local / 2 / sizeof(clvis_raster_tri)));
            std::size_t edge = std::min({pixel_group_edge, std::size_t(1) << tile_log2,
                                         floor_pow2(item_sizes.at(0)), floor_pow2(item_sizes.at(1))});
            while (edge > 1 && edge * edge > items) edge /= 2;
            fine_group = cl::NDRange(edge, edge);
            return;
        }
        // raster_fine.cl: a work-item per square of fine_square() pixels; no barriers, so any
        // group the kernel grants will do.
        std::size_t gx = std::min({fine_group_edge, max_group, floor_pow2(item_sizes.at(0))});
        std::size_t gy = std::min({fine_group_edge, max_group / gx, floor_pow2(item_sizes.at(1))});
        fine_group = cl::NDRange(gx, gy);
    }

    /// Bin entries per launch of raster_fine.cl that keep its loops within half the device's
    /// limit (half: a compiler may add passes that the source does not show). On Mesa 22.3's
    /// llvmpipe (65535) that is 330 entries for raster_fine.
    void plan_fine_chunks()
    {
        loop_limit = device.loop_limit();
        if (loop_limit == Device::Impl::loop_unlimited) return;
        std::uint32_t budget = loop_limit / 2;
        if (budget < CLVIS_FINE_TRIPS_FIXED + CLVIS_FINE_TRIPS_PER_ENTRY) // the larger of the two mappings'
            throw Error(Error::Kind::Device, device.info.name + " ends loops after " + std::to_string(loop_limit) +
                                                 " iterations per work-item, too few for the raster path");
        std::uint32_t fixed = pixel ? CLVIS_FINE_PIXEL_TRIPS_FIXED : CLVIS_FINE_TRIPS_FIXED;
        std::uint32_t per_entry = pixel ? CLVIS_FINE_PIXEL_TRIPS_PER_ENTRY : CLVIS_FINE_TRIPS_PER_ENTRY;
        fine_chunk = (budget - fixed) / per_entry;
    }

    /// A zeroed device buffer. Made from host zeros rather than left undefined: Oclgrind 21.10 reported
    /// kernel-written contents of fresh, uninitialised buffers as uninitialised once buffers of an
    /// earlier Renderer on the same device had been released.
    cl::Buffer make_buffer(std::size_t bytes) const
    {
        std::vector<unsigned char> zeros(bytes, 0);
        return cl::Buffer(device.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, bytes, zeros.data());
    }

    /// Makes `buffer` hold at least `needed` elements of `size` bytes, growing geometrically.
    void reserve(cl::Buffer& buffer, std::size_t& capacity, std::size_t needed, std::size_t size,
                 std::size_t first, const char* what)
    {
        if (needed <= capacity && buffer()) return;
        std::size_t grown = std::max({needed, capacity * 2, first});
        device.check_allocation(std::uint64_t(grown) * size, std::string("the raster path's ") + what);
        buffer = make_buffer(grown * size);
        capacity = grown;
    }

    /// Zeroes the first `count` 32-bit words of `buffer` (a kernel: Oclgrind then sees them written).
    void zero_words(Frame& frame, cl::Buffer& buffer, std::size_t count, const char* stage)
    {
        cl::Event done;
        zero.setArg(0, buffer);
        zero.setArg(1, cl_uint(count));
        frame.queue.enqueueNDRangeKernel(zero, cl::NullRange, cl::NDRange(round_up(count, zero_group)),
                                         cl::NDRange(zero_group), nullptr, &done);
        frame.stages->add(stage, done);
    }

    /// The counters once the sample's stages ran (the one blocking read-back of a sample).
    RasterCounts read_counts(Frame& frame)
    {
        struct { cl_uint listed[2]; cl_ulong entries, longest; } c{}; // the counters' layout
        frame.queue.enqueueReadBuffer(counters, CL_TRUE, 0, sizeof c, &c);
        return {cl_ulong(c.listed[0]) | cl_ulong(c.listed[1]) << 32, c.entries, c.longest};
    }

    /// Refuses a frame whose binning or scan loops would run past the device's loop limit.
    void check_loops(std::size_t tiles_x, std::size_t tiles_y) const
    {
        if (loop_limit == Device::Impl::loop_unlimited) return;
        std::size_t run = (tiles_x * tiles_y + scan_items - 1) / scan_items;
        // Passes through loop headers as plan_fine_chunks counts them, within half the limit.
        std::uint64_t bin_trips = std::uint64_t(tiles_y + 1) * (tiles_x + 2) + 64; // a triangle over every tile
        std::uint64_t scan_trips = 3 * (std::uint64_t(run) + 1) + 2 * (scan_items + 1) + 64;
        if (2 * std::max(bin_trips, scan_trips) > loop_limit)
            throw Error(Error::Kind::Limit,
                        device.info.name + " ends loops after " + std::to_string(loop_limit) +
                            " iterations per work-item, fewer than the raster path's binning of " +
                            std::to_string(tiles_x) + "x" + std::to_string(tiles_y) +
                            " tiles needs; use a larger tile size or a smaller image");
    }

    /// raster_setup_vertices: every vertex projected and snapped once.
    void project_vertices(const DeviceScene& scene, Frame& frame)
    {
        cl::Event projected_done;
        vertices.setArg(0, sizeof frame.gpu_camera, &frame.gpu_camera);
        vertices.setArg(1, scene.positions);
        vertices.setArg(2, cl_uint(scene.vertex_count));
        vertices.setArg(3, projected);
        frame.queue.enqueueNDRangeKernel(vertices, cl::NullRange, cl::NDRange(round_up(scene.vertex_count, vertex_group)),
                                         cl::NDRange(vertex_group), nullptr, &projected_done);
        frame.stages->add("setup", projected_done);
    }

    /// Runs a setup launch (`enqueue` sets its list arguments and enqueues it, signalling its
    /// event), bins and draws what it lists (merged with the keys when `merge`), reads the counts
    /// back; grows the list or bins and does it again until they held all (drawing again is
    /// harmless: atomic min, merged by min, or every key written again).
    template <class Enqueue> void draw_sample(Frame& frame, Enqueue enqueue, bool merge)
    {
        int tile = 1 << tile_log2;
        int tiles_x = (frame.width + tile - 1) / tile, tiles_y = (frame.height + tile - 1) / tile;
        check_loops(std::size_t(tiles_x), std::size_t(tiles_y));
        for (;;) {
            cl::Event done;
            zero_words(frame, counters, 4, "setup");
            enqueue(done);
            frame.stages->add("setup", done);
            bin_listed(frame, tiles_x, std::size_t(tiles_x) * std::size_t(tiles_y));
            launch_fine(frame, tiles_x, 0, merge);
            RasterCounts c = read_counts(frame);
            if (c.entries > 0xFFFFFFFFull)
                throw Error(Error::Kind::Limit, "the raster path's bins would hold " + std::to_string(c.entries) +
                                                    " entries, more than 32-bit offsets address");
            if (c.listed <= tri_capacity && c.entries <= entry_capacity) {
                // Long bins on a device that caps loops: the rest of each, merged.
                for (cl_ulong first = fine_chunk; first < c.longest; first += fine_chunk)
                    launch_fine(frame, tiles_x, first, true);
                return;
            }
            reserve(tris, tri_capacity, std::size_t(c.listed), sizeof(clvis_raster_tri), first_tri_capacity,
                    "list of triangles to bin");
            reserve(entries, entry_capacity, std::size_t(c.entries), sizeof(cl_uint), first_entry_capacity, "bins");
        }
    }

    /// Sets the arguments of a setup kernel from `first` on: projected, cull, keys, the list,
    /// its capacity, the counters and the region (raster_setup.cl's order).
    void set_setup_outputs(cl::Kernel& k, cl_uint first, Frame& frame)
    {
        k.setArg(first, projected);
        k.setArg(first + 1, cl_int(cull));
        k.setArg(first + 2, frame.keys);
        k.setArg(first + 3, tris);
        k.setArg(first + 4, cl_uint(std::min<std::size_t>(tri_capacity, 0xFFFFFFFFu)));
        k.setArg(first + 5, counters);
        k.setArg(first + 6, sizeof frame.region, &frame.region);
    }

    /// Draws frame.gpu_camera.sample: setup, binning, raster_fine.cl; projects the vertices first
    /// when `project` (once per frame: they do not depend on the sample).
    void render_sample(const DeviceScene& scene, Frame& frame, bool project)
    {
        if (project) project_vertices(scene, frame);
        draw_sample(frame, [&](cl::Event& done) {
            setup.setArg(0, sizeof frame.gpu_camera, &frame.gpu_camera);
            setup.setArg(1, scene.positions);
            setup.setArg(2, scene.indices);
            setup.setArg(3, cl_uint(scene.triangle_count));
            set_setup_outputs(setup, 4, frame);
            frame.queue.enqueueNDRangeKernel(setup, cl::NullRange,
                                             cl::NDRange(round_up(scene.triangle_count, setup_group)),
                                             cl::NDRange(setup_group), nullptr, &done);
        }, false);
    }

    /// Sets the item kernels' first arguments: camera, positions, (indices,) meshes, items, the chunk.
    cl_uint set_item_args(cl::Kernel& k, const InstancedScene& scene, const ItemChunk& c, Frame& frame, bool indices)
    {
        cl_uint a = 0;
        k.setArg(a++, sizeof frame.gpu_camera, &frame.gpu_camera);
        k.setArg(a++, scene.positions);
        if (indices) k.setArg(a++, scene.indices);
        k.setArg(a++, scene.meshes);
        k.setArg(a++, scene.items);
        k.setArg(a++, cl_uint(c.first_item));
        k.setArg(a++, cl_uint(c.end_item));
        return a;
    }

    /// A scene with instances: every chunk of items projected, set up and drawn per sample, each
    /// merged into the keys (cleared first, whatever the depth test).
    void render_items(const InstancedScene& scene, Frame& frame, std::size_t chunk_triangles)
    {
        clear_keys(clear, frame);
        int samples = 1 << frame.gpu_camera.sample_log2;
        for (const ItemChunk& c : scene.chunks(chunk_triangles)) {
            reserve(projected, projected_capacity, c.vertex_count, sizeof(clvis_raster_projected), 1,
                    "projected vertices");
            frame.gpu_camera.sample = 0;
            cl_uint a = set_item_args(item_vertices, scene, c, frame, false);
            item_vertices.setArg(a, cl_uint(c.vertex_count));
            item_vertices.setArg(a + 1, projected);
            cl::Event projected_done;
            frame.queue.enqueueNDRangeKernel(item_vertices, cl::NullRange,
                                             cl::NDRange(round_up(c.vertex_count, vertex_group)),
                                             cl::NDRange(vertex_group), nullptr, &projected_done);
            frame.stages->add("setup", projected_done);
            for (int sample = 0; sample < samples; ++sample) {
                frame.gpu_camera.sample = sample;
                draw_sample(frame, [&](cl::Event& done) {
                    cl_uint k = set_item_args(item_setup, scene, c, frame, true);
                    item_setup.setArg(k, cl_uint(c.triangle_count));
                    set_setup_outputs(item_setup, k + 1, frame);
                    frame.queue.enqueueNDRangeKernel(item_setup, cl::NullRange,
                                                     cl::NDRange(round_up(c.triangle_count, setup_group)),
                                                     cl::NDRange(setup_group), nullptr, &done);
                }, true);
            }
        }
        frame.gpu_camera.sample = 0;
    }

    /// Refuses an image larger than the raster path draws; makes the tile bins for the frame.
    void prepare_frame(Frame& frame)
    {
        int image_w = frame.gpu_camera.width, image_h = frame.gpu_camera.height; // the region's image
        if (image_w > CLVIS_MAX_IMAGE_SIZE || image_h > CLVIS_MAX_IMAGE_SIZE)
            throw Error(Error::Kind::Limit, "the raster path draws images of at most " +
                                                std::to_string(CLVIS_MAX_IMAGE_SIZE) + " pixels a side (" +
                                                std::to_string(image_w) + "x" + std::to_string(image_h) +
                                                " asked): its fixed-point edge functions hold no more");
        std::size_t tiles = std::size_t((frame.width + (1 << tile_log2) - 1) >> tile_log2) *
                            std::size_t((frame.height + (1 << tile_log2) - 1) >> tile_log2);
        if (tiles + 1 > tile_capacity) {
            device.check_allocation(std::uint64_t(tiles + 1) * sizeof(cl_uint), "the raster path's tile bins");
            tile_counts = make_buffer((tiles + 1) * sizeof(cl_uint));
            offsets = make_buffer((tiles + 1) * sizeof(cl_uint));
            cursors = make_buffer((tiles + 1) * sizeof(cl_uint));
            tile_capacity = tiles + 1;
            counts_zero = true;
        }
    }

    void render(const DeviceScene& scene, Frame& frame)
    {
        if (scene.triangle_count == 0) {
            prepare_frame(frame);
            clear_keys(clear, frame);
            return;
        }
        // Buffers whose size the frame fixes are made before anything is enqueued.
        reserve(projected, projected_capacity, scene.vertex_count, sizeof(clvis_raster_projected), 1,
                "projected vertices");
        prepare_frame(frame);
        // Tile ownership writes every key of the sample in raster_fine.cl: no clear.
        int samples = 1 << frame.gpu_camera.sample_log2;
        if (!owned) clear_keys(clear, frame);
        // One pass per sample (shared/samples.h): setup moves the snapped vertices by minus the
        // sample's offset, and every stage after it is the one-sample path's.
        for (int sample = 0; sample < samples; ++sample) {
            frame.gpu_camera.sample = sample;
            render_sample(scene, frame, sample == 0);
        }
        frame.gpu_camera.sample = 0;
    }

    /// Bins what setup listed (the count read on the device, the launch over the list's capacity):
    /// counts, scan, fill, within the bins' capacity.
    void bin_listed(Frame& frame, int tiles_x, std::size_t tile_count)
    {
        cl::Event counted, scanned, filled;
        if (!counts_zero) zero_words(frame, tile_counts, tile_count, "bin");
        counts_zero = false; // until raster_bin_scan is enqueued
        cl_uint list_capacity = cl_uint(std::min<std::size_t>(tri_capacity, 0xFFFFFFFFu));
        // A short list is binned by small work-groups: a close-up lists a few hundred triangles,
        // some over hundreds of tiles each, and PoCL hands a thread a run of work-groups at once.
        std::size_t group = tri_capacity <= small_bin_list ? std::min(bin_group, small_bin_group) : bin_group;
        cl::NDRange bin_global(round_up(tri_capacity, group)), bin_local(group);
        bin_count.setArg(0, tris);
        bin_count.setArg(1, counters);
        bin_count.setArg(2, list_capacity);
        bin_count.setArg(3, cl_int(tile_log2));
        bin_count.setArg(4, cl_int(tiles_x));
        bin_count.setArg(5, tile_counts);
        frame.queue.enqueueNDRangeKernel(bin_count, cl::NullRange, bin_global, bin_local, nullptr, &counted);
        frame.stages->add("bin", counted);
        bin_scan.setArg(0, tile_counts);
        bin_scan.setArg(1, cl_uint(tile_count));
        bin_scan.setArg(2, offsets);
        bin_scan.setArg(3, cursors);
        bin_scan.setArg(4, counters);
        bin_scan.setArg(5, cl::Local(scan_items * sizeof(cl_ulong)));
        frame.queue.enqueueNDRangeKernel(bin_scan, cl::NullRange, cl::NDRange(scan_items), cl::NDRange(scan_items),
                                         nullptr, &scanned);
        frame.stages->add("bin", scanned);
        counts_zero = true;
        bin_fill.setArg(0, tris);
        bin_fill.setArg(1, counters);
        bin_fill.setArg(2, list_capacity);
        bin_fill.setArg(3, cl_int(tile_log2));
        bin_fill.setArg(4, cl_int(tiles_x));
        bin_fill.setArg(5, cursors);
        bin_fill.setArg(6, entries);
        bin_fill.setArg(7, cl_uint(std::min<std::size_t>(entry_capacity, 0xFFFFFFFFu)));
        frame.queue.enqueueNDRangeKernel(bin_fill, cl::NullRange, bin_global, bin_local, nullptr, &filled);
        frame.stages->add("bin", filled);
    }

    /// raster_fine.cl over every square, for the bins' entries from `first` (a chunk of them on a
    /// device that caps loops, all elsewhere); a launch after the first merges with the keys.
    void launch_fine(Frame& frame, int tiles_x, cl_ulong first, bool merge)
    {
        fine.setArg(0, tris);
        fine.setArg(1, entries);
        fine.setArg(2, offsets);
        fine.setArg(3, cl_int(tile_log2));
        fine.setArg(4, cl_int(tiles_x));
        fine.setArg(5, sizeof frame.gpu_camera, &frame.gpu_camera);
        fine.setArg(6, frame.keys);
        fine.setArg(7, sizeof frame.region, &frame.region);
        fine.setArg(9, cl_uint(fine_chunk));
        fine.setArg(11, cl_uint(std::min<std::size_t>(entry_capacity, 0xFFFFFFFFu)));
        std::size_t square = pixel ? 1 : fine_square(); // pixels a side per work-item
        std::size_t squares_x = (std::size_t(frame.width) + square - 1) / square;
        std::size_t squares_y = (std::size_t(frame.height) + square - 1) / square;
        cl::NDRange fine_global(round_up(squares_x, fine_group[0]), round_up(squares_y, fine_group[1]));
        if (pixel) fine.setArg(12, cl::Local(fine_group[0] * fine_group[1] * sizeof(clvis_raster_tri)));
        cl::Event drawn;
        fine.setArg(8, cl_uint(first));
        fine.setArg(10, cl_int(merge || !owned || first > 0)); // setup drew (atomics), or an earlier launch did
        frame.queue.enqueueNDRangeKernel(fine, cl::NullRange, fine_global, fine_group, nullptr, &drawn);
        frame.stages->add("raster", drawn);
    }
};

RasterPipeline::RasterPipeline(Device::Impl& device, const RenderOptions& options)
    : impl_(std::make_unique<Impl>(device, options))
{
    if (options.raster_atomics == RasterAtomics::On && !device.info.int64_atomics)
        throw Error(Error::Kind::Device,
                    "the raster path's atomic depth test (raster atomics 'on') needs 64-bit atomics "
                    "(cl_khr_int64_base_atomics and cl_khr_int64_extended_atomics), which " +
                        device.info.name + " does not offer; use raster atomics 'auto' or 'off' (tile ownership)");
    Impl& m = *impl_;
    try {
        m.clear = make_clear_kernel(device);
        cl::Program setup = device.program("raster_setup", m.owned              ? "-DCLVIS_RASTER_OWNED"
                                                           : device.cpu_hints() ? "-DCLVIS_PREFETCH=1 -DCLVIS_PEEK=1"
                                                                                : "");
        m.vertices = cl::Kernel(setup, "raster_setup_vertices");
        m.setup = cl::Kernel(setup, "raster_setup");
        m.item_vertices = cl::Kernel(setup, "raster_setup_item_vertices");
        m.item_setup = cl::Kernel(setup, "raster_setup_items");
        cl::Program bin = device.program("raster_bin");
        m.zero = cl::Kernel(bin, "raster_bin_zero");
        m.bin_count = cl::Kernel(bin, "raster_bin_count");
        m.bin_scan = cl::Kernel(bin, "raster_bin_scan");
        m.bin_fill = cl::Kernel(bin, "raster_bin_fill");
        m.fine = cl::Kernel(device.program("raster_fine", device.cpu_hints() ? "-DCLVIS_PREFETCH=1" : ""),
                            m.pixel ? "raster_fine_pixel" : "raster_fine");
        m.pick_groups();
        m.plan_fine_chunks();
        m.counters = m.make_buffer(3 * sizeof(cl_ulong));
        std::size_t tris = probe_tri_capacity.load(), bins = probe_entry_capacity.load();
        tris = tris ? tris : first_tri_capacity, bins = bins ? bins : first_entry_capacity;
        m.reserve(m.tris, m.tri_capacity, tris, sizeof(clvis_raster_tri), tris, "list of triangles to bin");
        m.reserve(m.entries, m.entry_capacity, bins, sizeof(cl_uint), bins, "bins");
    } catch (const cl::Error& e) {
        throw_cl_error(e, "preparing the raster path on " + device.info.name);
    }
}

RasterPipeline::~RasterPipeline() = default;

void RasterPipeline::render(const DeviceScene& scene, Frame& frame) { impl_->render(scene, frame); }

void RasterPipeline::render(const InstancedScene& scene, Frame& frame, std::size_t chunk_triangles)
{
    impl_->prepare_frame(frame);
    impl_->render_items(scene, frame, chunk_triangles);
}

void set_raster_first_capacities(std::size_t triangles, std::size_t entries)
{
    probe_tri_capacity.store(triangles);
    probe_entry_capacity.store(entries);
}

} // namespace clvis::detail
