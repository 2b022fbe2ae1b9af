// Meshes, cameras and counts that several test files share.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/host_visibility.hpp>
#include <clvis/scene.hpp>
#include <clvis/scene_io.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace clvis::test {

/// A named scene seen by one camera at one size: the unit of the suites that loop over cases.
struct Case {
    std::string name;
    Scene scene;
    Camera camera;
    int width, height;
};

/// An item transform: `scale` times a turn by `yaw` about y (mirrored in y when yaw > 1), then
/// `offset`: instances of one prototype at many places, some of them mirrored.
inline Mat4 placed(double yaw, Vec3 offset, double scale)
{
    Mat4 m;
    m(0, 0) = scale * std::cos(yaw);
    m(0, 2) = scale * std::sin(yaw);
    m(2, 0) = -scale * std::sin(yaw);
    m(2, 2) = scale * std::cos(yaw);
    m(1, 1) = scale * (yaw > 1 ? -1 : 1);
    m(0, 3) = offset.x;
    m(1, 3) = offset.y;
    m(2, 3) = offset.z;
    return m;
}

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

/// One triangle as a mesh of its own.
inline MeshData triangle(float ax, float ay, float az, float bx, float by, float bz, float cx, float cy, float cz)
{
    MeshData m;
    m.positions = {ax, ay, az, bx, by, bz, cx, cy, cz};
    m.indices = {0, 1, 2};
    return m;
}

/// scenes/<file> of the source tree as a scene of one mesh.
inline Scene scene_file(const std::string& file)
{
    Scene s;
    s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/" + file));
    return s;
}

/// Pixels that hold a triangle.
inline std::size_t covered(const HostVisibility& v)
{
    std::size_t n = 0;
    for (auto id : v.ids) n += id != background_id;
    return n;
}

/// Pixels where two buffers differ in the id or in the depth's bits (bit-identical: 0).
inline std::size_t differing_bits(const HostVisibility& a, const HostVisibility& b)
{
    if (a.ids.size() != b.ids.size() || a.depth.size() != b.depth.size()) return a.ids.size() + b.ids.size() + 1;
    std::size_t n = 0;
    for (std::size_t i = 0; i < a.ids.size(); ++i) {
        std::uint32_t da, db;
        std::memcpy(&da, &a.depth[i], 4);
        std::memcpy(&db, &b.depth[i], 4);
        n += a.ids[i] != b.ids[i] || da != db;
    }
    return n;
}

/// A camera at `eye` looking at `target` with an up vector that is never parallel to the view.
inline Camera look(Vec3 eye, Vec3 target, double fov, double near, double far)
{
    Vec3 f = normalize(target - eye);
    Vec3 up = std::fabs(f.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    return Camera::perspective(eye, target, up, fov, near, far);
}

/// The two arrays hold the same bytes (and the same number of elements).
template <class T> bool same_bytes(const std::vector<T>& a, const std::vector<T>& b)
{
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

} // namespace clvis::test
