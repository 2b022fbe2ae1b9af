// The raster path: raster_setup.cl projects and clips every triangle, rasterizes the small ones
// at once (64-bit atomic min) and lists the others; raster_bin.cl bins those into tiles (count,
// scan, fill; on PoCL's CPU device a small frame's in one launch, raster_bin_small); raster_fine.cl
// rasterizes each tile's bin. Under tile ownership (RasterAtomics::Off,
// or Auto on a device without 64-bit atomics) setup lists every triangle and raster_fine.cl writes
// every key once (the background too), with no clear and no atomics on the keys. On a device that
// caps a work-item's loop iterations (Device::Impl::loop_limit), raster_fine.cl walks long bins in
// several launches. RasterMapping::Pixel runs raster_fine_pixel instead (a work-group per square
// of a tile, a work-item per pixel, the bin walked in batches through local memory). The list and
// bins keep their capacities from frame to frame; the bin kernels read the listed count on the
// device, the host reads the counts back once, after raster_fine.cl (which writes nothing for a
// bin past the capacity), and grows what overflowed and draws the sample again rather than drop.
// A scene with instances is drawn without its expansion, in chunks of whole items
// (frame/instanced_scene.hpp): per chunk raster_setup_item_vertices and raster_setup_items, then
// the stages above, every chunk's keys merged into the same buffer.
// This file enqueues; raster_sizing.cpp sizes groups and buffers (the state: raster_pipeline_impl.hpp).
#include "raster/raster_pipeline_impl.hpp"

#include "shared/raster_stream.h"

#include <clvis/error.hpp>

#include <algorithm>
#include <cstdint>
#include <string>

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

void RasterPipeline::Impl::zero_words(Frame& frame, cl::Buffer& buffer, std::size_t count, const char* stage)
{
    cl::Event done;
    zero.setArg(0, buffer);
    zero.setArg(1, cl_uint(count));
    frame.queue.enqueueNDRangeKernel(zero, cl::NullRange, cl::NDRange(round_up(count, zero_group)),
                                     cl::NDRange(zero_group), nullptr, &done);
    frame.stages->add(stage, done);
}

std::uint64_t RasterPipeline::Impl::frame_key_bytes(const Frame& frame)
{
    std::uint64_t pixels = std::uint64_t(frame.width) * std::uint64_t(frame.height);
    return (pixels << frame.gpu_camera.sample_log2) * std::uint64_t(frame.layers) * sizeof(cl_ulong);
}

void RasterPipeline::Impl::clear_frame(Frame& frame)
{
    cl_ulong count = frame_key_bytes(frame) / sizeof(cl_ulong);
    clear.setArg(0, frame.keys);
    clear.setArg(1, count);
    clear.setArg(2, cl_int(count * sizeof(cl_ulong) >= stream_bytes)); // past the cache (raster_stream.h)
    std::size_t items = std::size_t((count + CLVIS_CLEAR_RUN - 1) / CLVIS_CLEAR_RUN);
    cl::Event done;
    frame.queue.enqueueNDRangeKernel(clear, cl::NullRange, cl::NDRange(round_up(items, clear_group)),
                                     cl::NDRange(clear_group), nullptr, &done);
    frame.stages->add("clear", done);
}

RasterCounts RasterPipeline::Impl::read_counts(Frame& frame)
{
    CounterWords c{};
    if (counters_in_place) {
        frame.queue.finish(); // the sample's stages: the words hold their counts now
        const volatile CounterWords& w = counter_line.words;
        c.listed[0] = w.listed[0];
        c.listed[1] = w.listed[1];
        c.entries = w.entries;
        c.longest = w.longest;
    } else {
        frame.queue.enqueueReadBuffer(counters, CL_TRUE, 0, sizeof c, &c);
    }
    return {cl_ulong(c.listed[0]) | cl_ulong(c.listed[1]) << 32, c.entries, c.longest};
}

void RasterPipeline::Impl::project_vertices(const DeviceScene& scene, Frame& frame)
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

template <class Enqueue>
void RasterPipeline::Impl::draw_sample(Frame& frame, Enqueue enqueue, bool merge, std::size_t triangles)
{
    int tile = 1 << tile_log2;
    int tiles_x = (frame.width + tile - 1) / tile, tiles_y = (frame.height + tile - 1) / tile;
    check_loops(std::size_t(tiles_x), std::size_t(tiles_y));
    for (;;) {
        cl::Event done;
        // in place: no command of the queue touches them now (the last sample's counts were read
        // after its stages finished, and nothing before setup uses them)
        if (counters_in_place) {
            volatile CounterWords& w = counter_line.words;
            w.listed[0] = w.listed[1] = 0;
            w.entries = w.longest = 0;
        } else {
            zero_words(frame, counters, 4, "setup");
        }
        enqueue(done);
        frame.stages->add("setup", done);
        bin_listed(frame, tiles_x, std::size_t(tiles_x) * std::size_t(tiles_y), triangles);
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

void RasterPipeline::Impl::set_setup_outputs(cl::Kernel& k, cl_uint first, Frame& frame)
{
    k.setArg(first, projected);
    k.setArg(first + 1, cl_int(cull));
    k.setArg(first + 2, frame.keys);
    k.setArg(first + 3, tris);
    k.setArg(first + 4, cl_uint(std::min<std::size_t>(tri_capacity, 0xFFFFFFFFu)));
    k.setArg(first + 5, counters);
    k.setArg(first + 6, sizeof frame.region, &frame.region);
}

void RasterPipeline::Impl::render_sample(const DeviceScene& scene, Frame& frame, bool project)
{
    if (project) project_vertices(scene, frame);
    cl::Kernel& k = frame_owned && !owned ? owned_setup : setup;
    draw_sample(frame, [&](cl::Event& done) {
        k.setArg(0, sizeof frame.gpu_camera, &frame.gpu_camera);
        k.setArg(1, scene.positions);
        k.setArg(2, scene.indices);
        k.setArg(3, cl_uint(scene.triangle_count));
        set_setup_outputs(k, 4, frame);
        frame.queue.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(round_up(scene.triangle_count, setup_group)),
                                         cl::NDRange(setup_group), nullptr, &done);
    }, false, scene.triangle_count);
}

cl_uint RasterPipeline::Impl::set_item_args(cl::Kernel& k, const InstancedScene& scene, const ItemChunk& c, Frame& frame,
                                            bool indices)
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

void RasterPipeline::Impl::render_items(const InstancedScene& scene, Frame& frame, std::size_t chunk_triangles)
{
    frame_owned = owned;
    clear_frame(frame);
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
            }, true, c.triangle_count);
        }
    }
    frame.gpu_camera.sample = 0;
}

bool RasterPipeline::Impl::owns_frame(const DeviceScene& scene, const Frame& frame) const
{
    if (owned) return true;
    if (!own_small) return false;
    std::uint64_t keys = (std::uint64_t(frame.width) * std::uint64_t(frame.height)) << frame.gpu_camera.sample_log2;
    return std::uint64_t(scene.triangle_count) * owned_keys_per_triangle <= keys;
}

void RasterPipeline::Impl::render(const DeviceScene& scene, Frame& frame)
{
    if (scene.triangle_count == 0) {
        prepare_frame(frame);
        clear_frame(frame);
        return;
    }
    // Buffers whose size the frame fixes are made before anything is enqueued.
    reserve(projected, projected_capacity, scene.vertex_count, sizeof(clvis_raster_projected), 1,
            "projected vertices");
    prepare_frame(frame);
    // Tile ownership writes every key of the sample in raster_fine.cl: no clear.
    int samples = 1 << frame.gpu_camera.sample_log2;
    frame_owned = owns_frame(scene, frame);
    if (frame_owned && !owned && !owned_setup()) { // own_small's first such frame: its setup built
        owned_setup = cl::Kernel(device.program("raster_setup", owned_setup_options), "raster_setup");
        while (setup_group > granted(owned_setup)) setup_group /= 2; // a power of two within both grants
    }
    if (!frame_owned) clear_frame(frame);
    // One pass per sample (shared/samples.h): setup moves the snapped vertices by minus the
    // sample's offset, and every stage after it is the one-sample path's.
    for (int sample = 0; sample < samples; ++sample) {
        frame.gpu_camera.sample = sample;
        render_sample(scene, frame, sample == 0);
    }
    frame.gpu_camera.sample = 0;
}

void RasterPipeline::Impl::bin_listed(Frame& frame, int tiles_x, std::size_t tile_count, std::size_t triangles)
{
    cl_uint list_capacity = cl_uint(std::min<std::size_t>(tri_capacity, 0xFFFFFFFFu));
    cl_uint bin_capacity = cl_uint(std::min<std::size_t>(entry_capacity, 0xFFFFFFFFu));
    if (small_frames && tile_count <= small_frame_tiles &&
        std::uint64_t(triangles) * tile_count <= small_frame_work) {
        // A small frame on PoCL's CPU device: one launch, one thread, instead of three launches
        // over both (each launch of such a frame waits for the device's threads longer than its
        // work takes); the same bins.
        cl::Event binned;
        bin_small.setArg(0, tris);
        bin_small.setArg(1, counters);
        bin_small.setArg(2, list_capacity);
        bin_small.setArg(3, cl_int(tile_log2));
        bin_small.setArg(4, cl_int(tiles_x));
        bin_small.setArg(5, cl_uint(tile_count));
        bin_small.setArg(6, offsets);
        bin_small.setArg(7, counters);
        bin_small.setArg(8, entries);
        bin_small.setArg(9, bin_capacity);
        bin_small.setArg(10, cl::Local(tile_count * sizeof(cl_uint)));
        frame.queue.enqueueNDRangeKernel(bin_small, cl::NullRange, cl::NDRange(small_group), cl::NDRange(small_group),
                                         nullptr, &binned);
        frame.stages->add("bin", binned);
        return;
    }
    cl::Event counted, scanned, filled;
    if (!counts_zero) zero_words(frame, tile_counts, tile_count, "bin");
    counts_zero = false; // until raster_bin_scan is enqueued
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
    bin_fill.setArg(7, bin_capacity);
    frame.queue.enqueueNDRangeKernel(bin_fill, cl::NullRange, bin_global, bin_local, nullptr, &filled);
    frame.stages->add("bin", filled);
}

void RasterPipeline::Impl::launch_fine(Frame& frame, int tiles_x, cl_ulong first, bool merge)
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
    bool merged = merge || !frame_owned || first > 0; // setup drew (atomics), or an earlier launch did
    fine.setArg(10, cl_int(merged));
    if (!pixel) // every key written as it is: past the cache where the clear would stream (raster_stream.h)
        fine.setArg(12, cl_int(!merged && frame_key_bytes(frame) >= stream_bytes));
    frame.queue.enqueueNDRangeKernel(fine, cl::NullRange, fine_global, fine_group, nullptr, &drawn);
    frame.stages->add("raster", drawn);
}

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
        // The clear of the atomic depth test: a cache line per work-item, streamed past the cache
        // on PoCL's CPU device (kernels/visibility_clear.cl).
        m.clear = cl::Kernel(device.program("visibility_clear", device.cpu_hints() ? "-DCLVIS_STREAM=1" : ""),
                             "visibility_clear_lines");
        // Depth layers (RenderOptions::layers, shared/layers.h): compiled in only for K > 1.
        std::string layers = options.layers > 1 ? "-DCLVIS_LAYERS=" + std::to_string(options.layers) : "";
        auto with_layers = [&](std::string define) {
            return layers.empty() ? define : define.empty() ? layers : define + " " + layers;
        };
        m.own_small = options.raster_atomics == RasterAtomics::Auto && !m.owned && !m.pixel && device.cpu_hints();
        m.owned_setup_options = with_layers("-DCLVIS_RASTER_OWNED");
        cl::Program setup = device.program("raster_setup", with_layers(m.owned              ? "-DCLVIS_RASTER_OWNED"
                                                                       : device.cpu_hints() ? "-DCLVIS_PREFETCH=1 -DCLVIS_PEEK=1"
                                                                                            : ""));
        m.vertices = cl::Kernel(setup, "raster_setup_vertices");
        m.setup = cl::Kernel(setup, "raster_setup");
        m.item_vertices = cl::Kernel(setup, "raster_setup_item_vertices");
        m.item_setup = cl::Kernel(setup, "raster_setup_items");
        cl::Program bin = device.program("raster_bin");
        m.zero = cl::Kernel(bin, "raster_bin_zero");
        m.bin_count = cl::Kernel(bin, "raster_bin_count");
        m.bin_scan = cl::Kernel(bin, "raster_bin_scan");
        m.bin_fill = cl::Kernel(bin, "raster_bin_fill");
        m.bin_small = cl::Kernel(bin, "raster_bin_small");
        m.fine = cl::Kernel(device.program("raster_fine", with_layers(device.cpu_hints() ? "-DCLVIS_PREFETCH=1 -DCLVIS_STREAM=1" : "")),
                            m.pixel ? "raster_fine_pixel" : "raster_fine");
        m.pick_groups();
        m.plan_fine_chunks();
        m.make_growable_buffers();
    } catch (const cl::Error& e) {
        throw_cl_error(e, "preparing the raster path on " + device.info.name);
    }
}

RasterPipeline::~RasterPipeline() = default;

bool RasterPipeline::frame_owned() const { return impl_->frame_owned; }

void RasterPipeline::render(const DeviceScene& scene, Frame& frame) { impl_->render(scene, frame); }

void RasterPipeline::render(const InstancedScene& scene, Frame& frame, std::size_t chunk_triangles)
{
    impl_->prepare_frame(frame);
    impl_->render_items(scene, frame, chunk_triangles);
}

} // namespace clvis::detail
