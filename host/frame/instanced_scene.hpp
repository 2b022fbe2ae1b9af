// A scene with instances on the device without its expansion (kernels/shared/scene_items.h): the
// meshes once and 64 bytes per item. The raster path draws it in chunks of whole items, so its
// scratch grows with a chunk, not with the scene.
#pragma once

#include "runtime/cl.hpp"

#include "shared/scene_items.h"

#include <clvis/device.hpp>
#include <clvis/scene.hpp>

#include <cstdint>
#include <vector>

namespace clvis::detail {

/// Consecutive items [first_item, end_item): their triangles are ids first_id .. + triangle_count.
struct ItemChunk {
    std::uint32_t first_item = 0, end_item = 0;
    std::uint32_t first_id = 0, triangle_count = 0;
    std::uint32_t vertex_count = 0; ///< the items' vertices (each item's mesh's, once per item)
};

struct InstancedScene {
    cl::Buffer positions; ///< float x, y, z per mesh vertex: prototypes object space, plain meshes world
    cl::Buffer indices;   ///< uint, 3 per mesh triangle, local to the mesh
    cl::Buffer meshes;    ///< clvis_item_mesh per mesh
    cl::Buffer items;     ///< clvis_item per item with triangles, in id order
    std::vector<clvis_item> host_items;
    std::vector<clvis_item_mesh> host_meshes;
    std::uint32_t triangle_count = 0;
    std::uint64_t device_bytes = 0; ///< the four buffers together

    /// Uploads `scene` (replacing what was there). Error(Limit) where a buffer does not fit.
    void upload(const Scene& scene, Device::Impl& device, cl::CommandQueue& queue);
    /// Splits the items into chunks of at most `triangles` triangles each (an item larger than
    /// that is a chunk of its own), in id order.
    std::vector<ItemChunk> chunks(std::size_t triangles) const;
};

/// The raster path's triangles per chunk of an instanced scene unless a test sets fewer
/// (detail::set_raster_chunk): a few million keep its scratch to a few hundred MB.
constexpr std::size_t default_raster_chunk = std::size_t(1) << 21;

} // namespace clvis::detail
