// Procedural meshes for tests and benchmarks, each with a requested triangle count, seeded and
// deterministic: the same arguments give the same bits on every machine.
#pragma once

#include <clvis/scene.hpp>

#include <cstdint>

namespace clvis {

/// A closed UV sphere of radius 1 at the origin with about `triangles` triangles (at least 8).
MeshData make_uv_sphere(std::size_t triangles);
/// A height-field grid (terrain) over [-1, 1]^2 in x, z with about `triangles` triangles.
MeshData make_grid(std::size_t triangles, std::uint64_t seed);
/// A soup of `triangles` random small triangles in the unit cube.
MeshData make_soup(std::size_t triangles, std::uint64_t seed);

} // namespace clvis
