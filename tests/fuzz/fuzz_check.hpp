// What every fuzz target asserts about a mesh a parser accepted: the MeshData invariants of
// scene.hpp, and that a Scene takes it. A violation aborts, which libFuzzer reports as a crash.
#pragma once

#include <clvis/error.hpp>
#include <clvis/scene.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace clvis::fuzz {

[[noreturn]] inline void broken(const char* what)
{
    std::fprintf(stderr, "parser accepted a broken mesh: %s\n", what);
    std::abort();
}

inline void check_mesh(const MeshData& m)
{
    if (m.positions.size() % 3 || m.indices.size() % 3) broken("sizes not multiples of 3");
    if (m.indices.empty()) broken("no triangles");
    if (!m.normals.empty() && m.normals.size() != m.positions.size()) broken("normals not one per vertex");
    for (float v : m.positions)
        if (!std::isfinite(v)) broken("non-finite position");
    for (std::uint32_t i : m.indices)
        if (i >= m.vertex_count()) broken("index out of range");
    try {
        Scene s;
        s.add_mesh(m);
    } catch (const Error&) {
        broken("Scene::add_mesh refused it");
    }
}

} // namespace clvis::fuzz
