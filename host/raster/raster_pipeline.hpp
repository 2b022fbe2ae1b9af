// The raster path's pipeline (raster_pipeline.cpp, its sizing in raster_sizing.cpp): setup, bin
// and fine kernels over the frame layer's scene and frame (frame/frame.hpp). Made and driven by
// the Renderer (render/), which it never includes.
#pragma once

#include "frame/frame.hpp"

#include <clvis/device.hpp>
#include <clvis/render_options.hpp>

#include <cstddef>
#include <memory>

namespace clvis::detail {

/// The raster path's first list of triangles to bin (elements): a frame that lists more grows it
/// and runs setup again (tests/oclgrind_test.cpp drives that path).
constexpr std::size_t raster_first_tri_capacity = std::size_t(1) << 12;

/// The raster tile edge (log2) that RenderOptions::tile_size asks for (0: the default).
int raster_tile_log2(const RenderOptions& options);
/// Whether the raster path runs by tile ownership on `info` under `options` (RasterAtomics).
bool raster_owned(const DeviceInfo& info, const RenderOptions& options);

/// The raster path. Its options name Square or Pixel: the Renderer resolves Auto first
/// (render/raster_tune.hpp).
class RasterPipeline {
public:
    RasterPipeline(Device::Impl& device, const RenderOptions& options);
    ~RasterPipeline();
    /// Enqueues every kernel of the raster path for `frame` (the clear included) and returns
    /// without waiting; the Renderer waits and collects the stage times.
    void render(const DeviceScene& scene, Frame& frame);
    /// The same for a scene with instances, without its expansion: chunks of whole items of at
    /// most `chunk_triangles` triangles (or one item), each merged into the keys.
    void render(const InstancedScene& scene, Frame& frame, std::size_t chunk_triangles);
    /// Whether the last frame enqueued was drawn by tile ownership (RasterAtomics::Off's depth
    /// test, which Auto picks for a device without 64-bit atomics and, on PoCL's CPU device, for a
    /// frame of few triangles) rather than by 64-bit atomics.
    bool frame_owned() const;

    struct Impl;

private:
    std::unique_ptr<Impl> impl_;
};

/// First capacities of the raster path's list of triangles to bin and of its bins (elements) for
/// raster pipelines made from now on, in this process (0: the defaults). Tests make them tiny to
/// drive the growth and redraw of a frame whose list or bins overflowed.
void set_raster_first_capacities(std::size_t triangles, std::size_t entries);

/// Whether raster pipelines made from now on, in this process, bin small frames in one launch
/// (raster_bin_small): 1 always, 0 never, -1 (the default) where the device is PoCL's CPU device
/// without a loop limit. Tests run the one kernel on Oclgrind and the three on PoCL.
void set_raster_small_frames(int use);

} // namespace clvis::detail
