// Procedural meshes for tests and benchmarks, each with a requested triangle count, seeded and
// deterministic: the same arguments give the same bits on every machine.
#pragma once

#include <clvis/scene.hpp>

#include <cstdint>

namespace clvis {

/// A closed UV sphere of radius 1 at the origin with about `triangles` triangles (at least 8):
/// poles as fans, every edge shared by exactly two triangles, wound counter-clockwise outside.
MeshData make_uv_sphere(std::size_t triangles);
/// A height-field grid (terrain) over [-1, 1]^2 in x, z with about `triangles` triangles (at
/// least 2), heights within about +-0.3, facing +y.
MeshData make_grid(std::size_t triangles, std::uint64_t seed);
/// A soup of `triangles` random small triangles in the unit cube [0, 1]^3, edges about
/// 2 / sqrt(triangles) long (at most 0.25). All three throw Error(InvalidArgument) past 2^31.
MeshData make_soup(std::size_t triangles, std::uint64_t seed);

} // namespace clvis
