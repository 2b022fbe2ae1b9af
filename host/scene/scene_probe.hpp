// What tests may see inside Scene beyond its public interface.
#pragma once

#include <atomic>
#include <cstdint>

namespace clvis::detail {

/// Vertices of every expansion of a scene with instances Scene::world_positions() has built in
/// this process (all scenes, summed; a plain scene's world positions are not counted): the tests of "instances never expand" read it before and after the entry points.
extern std::atomic<std::uint64_t> expansion_vertices_built;

} // namespace clvis::detail
