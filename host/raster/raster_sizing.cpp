// The raster path's sizing: the tile edge and depth test that options and device ask for,
// work-group sizes within each kernel's grant, the loop budget of a device that caps loops, and
// the growable list, bins and tile bins (raster_pipeline_impl.hpp; launches in raster_pipeline.cpp).
#include "raster/raster_pipeline_impl.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <atomic>
#include <string>
#include <vector>

namespace clvis::detail {

namespace {

/// Tile edge in pixels when RenderOptions::tile_size is 0 (log2).
constexpr int default_tile_log2 = 4;
/// The probe's first capacities (set_raster_first_capacities; 0: the defaults).
std::atomic<std::size_t> probe_tri_capacity{0}, probe_entry_capacity{0};
/// The probe's choice of raster_bin_small (set_raster_small_frames; -1: the device's).
std::atomic<int> probe_small_frames{-1};
/// Bytes of host zeros that make_buffer writes a buffer from, a block at a time.
constexpr std::size_t zero_block = std::size_t(1) << 20;

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

void set_raster_first_capacities(std::size_t triangles, std::size_t entries)
{
    probe_tri_capacity.store(triangles);
    probe_entry_capacity.store(entries);
}

void set_raster_small_frames(int use) { probe_small_frames.store(use < 0 ? -1 : use > 0 ? 1 : 0); }

void RasterPipeline::Impl::pick_groups()
{
    clear_group = std::min(linear_group, floor_pow2(granted(clear)));
    if (cl_ulong cache = device.device.getInfo<CL_DEVICE_GLOBAL_MEM_CACHE_SIZE>(); cache > 0) stream_bytes = cache / 4;
    zero_group = std::min(linear_group, floor_pow2(granted(zero)));
    vertex_group = std::min({linear_group, floor_pow2(granted(vertices)), floor_pow2(granted(item_vertices))});
    setup_group = std::min({linear_group, floor_pow2(granted(setup)), floor_pow2(granted(item_setup))});
    bin_group = std::min({linear_group, floor_pow2(granted(bin_count)), floor_pow2(granted(bin_fill))});
    scan_items = std::min(scan_group, floor_pow2(granted(bin_scan)));
    small_group = std::min(small_frame_group, floor_pow2(granted(bin_small)));
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

void RasterPipeline::Impl::plan_fine_chunks()
{
    loop_limit = device.loop_limit();
    int forced = probe_small_frames.load();
    small_frames = forced >= 0 ? forced == 1 : device.cpu_hints() && loop_limit == Device::Impl::loop_unlimited;
    if (loop_limit == Device::Impl::loop_unlimited) return;
    std::uint32_t budget = loop_limit / 2;
    if (budget < CLVIS_FINE_TRIPS_FIXED + CLVIS_FINE_TRIPS_PER_ENTRY) // the larger of the two mappings'
        throw Error(Error::Kind::Device, device.info.name + " ends loops after " + std::to_string(loop_limit) +
                                             " iterations per work-item, too few for the raster path");
    std::uint32_t fixed = pixel ? CLVIS_FINE_PIXEL_TRIPS_FIXED : CLVIS_FINE_TRIPS_FIXED;
    std::uint32_t per_entry = pixel ? CLVIS_FINE_PIXEL_TRIPS_PER_ENTRY : CLVIS_FINE_TRIPS_PER_ENTRY;
    fine_chunk = (budget - fixed) / per_entry;
}

cl::Buffer RasterPipeline::Impl::make_buffer(std::size_t bytes) const
{
    // Zeroed from one small block of host zeros, a write per block on a queue of its own (finished
    // before the buffer is used): no host copy of the buffer's size, which on a CPU device (whose
    // buffers are host memory) doubled the peak of a large list for a moment (issue 37).
    static const std::vector<unsigned char> zeros(zero_block, 0);
    if (bytes <= zero_block)
        return cl::Buffer(device.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, bytes,
                          const_cast<unsigned char*>(zeros.data()));
    cl::Buffer buffer(device.context, CL_MEM_READ_WRITE, bytes);
    cl::CommandQueue queue(device.context, device.device);
    for (std::size_t at = 0; at < bytes; at += zero_block)
        queue.enqueueWriteBuffer(buffer, CL_FALSE, at, std::min(zero_block, bytes - at), zeros.data());
    queue.finish();
    return buffer;
}

void RasterPipeline::Impl::reserve(cl::Buffer& buffer, std::size_t& capacity, std::size_t needed, std::size_t size,
                                   std::size_t first, const char* what)
{
    if (needed <= capacity && buffer()) return;
    std::size_t grown = std::max({needed, capacity * 2, first});
    device.check_allocation(std::uint64_t(grown) * size, std::string("the raster path's ") + what);
    buffer = make_buffer(grown * size);
    capacity = grown;
}

void RasterPipeline::Impl::make_growable_buffers()
{
    static_assert(sizeof(CounterWords) == 3 * sizeof(cl_ulong), "the counters' layout (raster_setup.cl)");
    counters_in_place = device.host_memory_in_place();
    counter_line = CounterLine{};
    counters = counters_in_place ? cl::Buffer(device.context, CL_MEM_READ_WRITE | CL_MEM_USE_HOST_PTR,
                                              sizeof(CounterWords), &counter_line.words)
                                 : make_buffer(3 * sizeof(cl_ulong));
    std::size_t tris_first = probe_tri_capacity.load(), bins_first = probe_entry_capacity.load();
    if (tris_first == 0) tris_first = first_tri_capacity;
    if (bins_first == 0) bins_first = first_entry_capacity;
    reserve(tris, tri_capacity, tris_first, sizeof(clvis_raster_tri), tris_first, "list of triangles to bin");
    reserve(entries, entry_capacity, bins_first, sizeof(cl_uint), bins_first, "bins");
}

void RasterPipeline::Impl::check_loops(std::size_t tiles_x, std::size_t tiles_y) const
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

void RasterPipeline::Impl::prepare_frame(Frame& frame)
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

} // namespace clvis::detail
