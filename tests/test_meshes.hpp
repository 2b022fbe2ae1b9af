// Meshes that several test files build by hand.
#pragma once

#include <clvis/scene.hpp>

#include <cstdint>

namespace clvis::test {

/// Two triangles per cell of an (n + 1) x (n + 1) vertex lattice laid out row by row, the
/// diagonal alternating from cell to cell so that vertices meet 4 and 8 triangles.
inline void add_grid_triangles(MeshData& m, int n)
{
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n) + 1, d = c + 1;
            if ((i + j) % 2) m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
            else m.indices.insert(m.indices.end(), {a, b, c, b, d, c});
        }
}

} // namespace clvis::test
