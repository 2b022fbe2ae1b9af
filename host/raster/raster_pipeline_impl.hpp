// The raster path's state behind RasterPipeline (raster_pipeline.hpp), shared by its launches
// (raster_pipeline.cpp: kernels made, arguments set, stages enqueued, a sample drawn again until
// its list and bins held it) and its sizing (raster_sizing.cpp: work-group sizes, loop budgets,
// the growable buffers and the tile bins).
#pragma once

#include "frame/instanced_scene.hpp"
#include "raster/raster_pipeline.hpp"
#include "runtime/cl_runtime.hpp"

#include "shared/raster.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

namespace clvis::detail {

/// The counts read back once a sample: triangles listed, bin entries in all, the longest bin's.
struct RasterCounts { cl_ulong listed, entries, longest; };

struct RasterPipeline::Impl {
    /// Work-items per group of the one-dimensional kernels (setup, bin count and fill), at most.
    static constexpr std::size_t linear_group = 64;
    /// Lists of binned triangles up to this capacity are binned by work-groups of small_bin_group
    /// (bin_listed says why).
    static constexpr std::size_t small_bin_list = std::size_t(1) << 14, small_bin_group = 4;
    /// Work-items per group edge of raster_fine.cl (each owns a square of pixels), at most.
    static constexpr std::size_t fine_group_edge = 4;
    /// Pixels per group edge of raster_fine_pixel, at most (fewer where the grant, local memory or tile ask).
    static constexpr std::size_t pixel_group_edge = 16;
    /// Work-items of the single work-group of raster_bin_scan, at most.
    static constexpr std::size_t scan_group = 256;
    /// raster_bin_small (bin_listed): a sample of at most small_frame_tiles tiles whose
    /// triangles times tiles are at most small_frame_work is binned by one work-group of
    /// small_frame_group work-items (one: PoCL runs a group's work-items as a loop anyway; 16 and
    /// 64 measured no faster). Measured on PoCL's CPU device (2 threads): 1k triangles at 256x144
    /// (144 tiles) and 384x256 and 512x512, 4k at 384x256 faster in one launch; 4k at 512x512
    /// (4M) slower.
    static constexpr std::size_t small_frame_tiles = 1024, small_frame_group = 1;
    static constexpr std::uint64_t small_frame_work = std::uint64_t(1) << 21;
    /// First capacities of the growable buffers (elements); they double or jump to what a frame needs.
    static constexpr std::size_t first_tri_capacity = raster_first_tri_capacity,
                                 first_entry_capacity = std::size_t(1) << 14;

    Device::Impl& device;
    int tile_log2;
    int cull = CLVIS_CULL_NONE;
    bool owned = false; ///< tile ownership: raster_setup.cl built with CLVIS_RASTER_OWNED
    /// RasterAtomics::Auto on PoCL's CPU device (square mapping): a frame of few triangles for its
    /// keys (owns_frame) is drawn by tile ownership too, with owned_setup (the same keys).
    bool own_small = false;
    bool frame_owned = false; ///< the frame being drawn is drawn by tile ownership
    /// Keys per triangle, at least, of a frame that own_small draws by tile ownership: there,
    /// binning every triangle costs less than the clear and the merge's reads it saves (issue 37;
    /// on PoCL at 1080p a 64k-triangle sphere still gains, a 256k one loses).
    static constexpr std::size_t owned_keys_per_triangle = 16;
    bool pixel = false; ///< RasterMapping::Pixel: raster_fine_pixel
    std::uint32_t loop_limit = Device::Impl::loop_unlimited; ///< the device's, measured
    std::uint32_t fine_chunk = 0xFFFFFFFFu; ///< bin entries per launch of raster_fine.cl
    cl::Kernel clear, zero, vertices, setup, bin_count, bin_scan, bin_fill, bin_small, fine;
    cl::Kernel item_vertices, item_setup; ///< the same two stages for a chunk of items
    cl::Kernel owned_setup; ///< raster_setup built with CLVIS_RASTER_OWNED, for own_small (made on first use)
    std::string owned_setup_options; ///< its build options
    /// Clears of at least this many bytes stream their lines past the cache (visibility_clear_lines):
    /// a quarter of the device's global memory cache, or 4 MiB where it reports none.
    std::uint64_t stream_bytes = std::uint64_t(4) << 20;
    std::size_t clear_group = 1, zero_group = 1, vertex_group = 1, setup_group = 1, bin_group = 1, scan_items = 1,
                small_group = 1;
    /// raster_bin_small for small frames (bin_listed): PoCL's CPU device, no loop limit
    bool small_frames = false;
    cl::NDRange fine_group;
    cl::Buffer counters; ///< uint[2] triangles listed by setup (low, high word), ulong bin entries, ulong longest bin
    /// The counters' host words where the device works on host memory in place
    /// (Device::Impl::host_memory_in_place): `counters` is a buffer over them, which the host
    /// zeroes before a sample's setup and reads after its stages finish, with no command of its
    /// own (each PoCL command waits for its worker threads to wake).
    struct CounterWords {
        cl_uint listed[2];
        cl_ulong entries, longest;
    };
    struct alignas(64) CounterLine { // a cache line of their own: the kernels' atomics share it with nothing
        CounterWords words;
    } counter_line{};
    bool counters_in_place = false;
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

    // Sizing (raster_sizing.cpp).
    void pick_groups();
    /// Bin entries per launch of raster_fine.cl that keep its loops within half the device's
    /// limit (half: a compiler may add passes that the source does not show). On Mesa 22.3's
    /// llvmpipe (65535) that is 330 entries for raster_fine.
    void plan_fine_chunks();
    /// A zeroed device buffer. Made from host zeros rather than left undefined: Oclgrind 21.10 reported
    /// kernel-written contents of fresh, uninitialised buffers as uninitialised once buffers of an
    /// earlier Renderer on the same device had been released.
    cl::Buffer make_buffer(std::size_t bytes) const;
    /// Makes `buffer` hold at least `needed` elements of `size` bytes, growing geometrically.
    void reserve(cl::Buffer& buffer, std::size_t& capacity, std::size_t needed, std::size_t size,
                 std::size_t first, const char* what);
    /// The counters and the list and bins at their first capacities (set_raster_first_capacities).
    void make_growable_buffers();
    /// Refuses a frame whose binning or scan loops would run past the device's loop limit.
    void check_loops(std::size_t tiles_x, std::size_t tiles_y) const;
    /// Refuses an image larger than the raster path draws; makes the tile bins for the frame.
    void prepare_frame(Frame& frame);

    // Launches (raster_pipeline.cpp).
    /// Bytes of the frame's keys: every sample and layer.
    static std::uint64_t frame_key_bytes(const Frame& frame);
    /// Writes the background into every key of the frame (every sample and layer): visibility_clear_lines.
    void clear_frame(Frame& frame);
    /// Zeroes the first `count` 32-bit words of `buffer` (a kernel: Oclgrind then sees them written).
    void zero_words(Frame& frame, cl::Buffer& buffer, std::size_t count, const char* stage);
    /// The counters once the sample's stages ran (the one blocking read-back of a sample).
    RasterCounts read_counts(Frame& frame);
    /// raster_setup_vertices: every vertex projected and snapped once.
    void project_vertices(const DeviceScene& scene, Frame& frame);
    /// Runs a setup launch (`enqueue` sets its list arguments and enqueues it, signalling its
    /// event), bins and draws what it lists (merged with the keys when `merge`), reads the counts
    /// back; grows the list or bins and does it again until they held all (drawing again is
    /// harmless: atomic min, merged by min, or every key written again). `triangles`: the scene's
    /// or the chunk's, which pick the binning (bin_listed).
    template <class Enqueue> void draw_sample(Frame& frame, Enqueue enqueue, bool merge, std::size_t triangles);
    /// Sets the arguments of a setup kernel from `first` on: projected, cull, keys, the list,
    /// its capacity, the counters and the region (raster_setup.cl's order).
    void set_setup_outputs(cl::Kernel& k, cl_uint first, Frame& frame);
    /// Draws frame.gpu_camera.sample: setup, binning, raster_fine.cl; projects the vertices first
    /// when `project` (once per frame: they do not depend on the sample).
    void render_sample(const DeviceScene& scene, Frame& frame, bool project);
    /// Sets the item kernels' first arguments: camera, positions, (indices,) meshes, items, the chunk.
    cl_uint set_item_args(cl::Kernel& k, const InstancedScene& scene, const ItemChunk& c, Frame& frame, bool indices);
    /// A scene with instances: every chunk of items projected, set up and drawn per sample, each
    /// merged into the keys (cleared first, whatever the depth test).
    void render_items(const InstancedScene& scene, Frame& frame, std::size_t chunk_triangles);
    /// Whether `frame` of `scene` is drawn by tile ownership: always when owned, and own_small's
    /// frames of at most one triangle per owned_keys_per_triangle keys.
    bool owns_frame(const DeviceScene& scene, const Frame& frame) const;
    /// Every sample of `frame` for a scene without instances (the clear included unless owned).
    void render(const DeviceScene& scene, Frame& frame);
    /// Bins what setup listed (the count read on the device, the launch over the list's capacity)
    /// into tile_count tiles: counts, scan, fill, within the bins' capacity; in one launch
    /// (raster_bin_small) for a small frame, by tile_count and the scene's or chunk's `triangles`.
    void bin_listed(Frame& frame, int tiles_x, std::size_t tile_count, std::size_t triangles);
    /// raster_fine.cl over every square, for the bins' entries from `first` (a chunk of them on a
    /// device that caps loops, all elsewhere); a launch after the first merges with the keys.
    void launch_fine(Frame& frame, int tiles_x, cl_ulong first, bool merge);
};

} // namespace clvis::detail
