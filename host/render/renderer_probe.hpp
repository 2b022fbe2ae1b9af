// What tests and benchmarks may see and set inside a Renderer beyond its public interface.
#pragma once

#include <clvis/renderer.hpp>

#include <cstddef>
#include <cstdint>

namespace clvis::detail {

/// Triangles per chunk of items when the raster path draws a scene with instances
/// (default_raster_chunk; at least 1).
void set_raster_chunk(Renderer& renderer, std::size_t triangles);
/// Whether the expansion (Scene::world_positions) is on the device.
bool expansion_uploaded(Renderer& renderer);
/// Device bytes of the scene's meshes and item records (frame/instanced_scene.hpp), 0 before
/// the raster path first draws a scene with instances.
std::uint64_t item_device_bytes(Renderer& renderer);

} // namespace clvis::detail
