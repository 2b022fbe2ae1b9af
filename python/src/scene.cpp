// Scenes from Python: meshes from NumPy arrays (one conversion where a dtype or layout differs,
// then copied into the scene), from files (clvis.load_mesh, clvis.load_scene) or procedural;
// bounds; positions and transforms changed for Renderer.update.
#include "arrays.hpp"

#include <nanobind/stl/array.h>
#include <nanobind/stl/filesystem.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

namespace clvis::python {

namespace {

/// The arrays of a mesh as views into it (no copy), valid while the Mesh object lives.
nb::object rows_view(const std::vector<float>& v, nb::handle owner)
{
    if (v.empty()) return nb::none();
    return nb::cast(numpy_view(v.data(), {v.size() / 3, 3}, owner));
}

void bind_mesh(nb::module_& m)
{
    nb::class_<MeshData>(m, "Mesh",
                         "One mesh as arrays, from clvis.load_mesh or the procedural makers; add it with Scene.add_mesh.\n\n"
                         "Example:\n    mesh = clvis.load_mesh('scenes/spot.obj')\n    print(mesh.positions.shape, mesh.indices.shape)")
        .def_ro("name", &MeshData::name)
        .def_prop_ro("positions", [](nb::handle self) { return rows_view(nb::cast<MeshData&>(self).positions, self); },
                     "(V, 3) float32, read-only, a view into the mesh.")
        .def_prop_ro(
            "indices",
            [](nb::handle self) {
                const auto& v = nb::cast<MeshData&>(self).indices;
                return nb::cast(numpy_view(v.data(), {v.size() / 3, 3}, self));
            },
            "(T, 3) uint32, read-only, a view into the mesh.")
        .def_prop_ro("normals", [](nb::handle self) { return rows_view(nb::cast<MeshData&>(self).normals, self); },
                     "(V, 3) float32 per-vertex normals, or None.")
        .def_prop_ro("vertex_count", &MeshData::vertex_count)
        .def_prop_ro("triangle_count", &MeshData::triangle_count)
        .def("__repr__", [](const MeshData& d) {
            return "<clvis.Mesh '" + d.name + "': " + std::to_string(d.vertex_count()) + " vertices, " +
                   std::to_string(d.triangle_count()) + " triangles>";
        });

    m.def(
        "load_mesh",
        [](const std::filesystem::path& path) {
            nb::gil_scoped_release nogil;
            return load_mesh(path.string());
        },
        nb::arg("path"),
        "Reads an OBJ, PLY or STL file into a Mesh. Raises IoError naming the file and line.\n\n"
        "Example:\n    scene = clvis.Scene()\n    scene.add_mesh(clvis.load_mesh('scenes/stanford-bunny.obj'))");
    m.def("make_uv_sphere", &make_uv_sphere, nb::arg("triangles"),
          "A closed UV sphere of radius 1 with about `triangles` triangles.");
    m.def("make_grid", &make_grid, nb::arg("triangles"), nb::arg("seed") = 1,
          "A height-field grid over [-1, 1]^2 in x, z with about `triangles` triangles, facing +y.");
    m.def("make_soup", &make_soup, nb::arg("triangles"), nb::arg("seed") = 1,
          "`triangles` random small triangles in the unit cube.");
}

void bind_bounds(nb::module_& m)
{
    nb::class_<Bounds>(m, "Bounds", "An axis-aligned box (Scene.bounds()); empty until a point is added.")
        .def(nb::init<>())
        .def(
            "__init__",
            [](Bounds* b, std::array<double, 3> lo, std::array<double, 3> hi) {
                new (b) Bounds();
                b->add(to_vec3(lo));
                b->add(to_vec3(hi));
            },
            nb::arg("lo"), nb::arg("hi"))
        .def_prop_ro("lo", [](const Bounds& b) { return from_vec3(b.lo); })
        .def_prop_ro("hi", [](const Bounds& b) { return from_vec3(b.hi); })
        .def_prop_ro("empty", &Bounds::empty)
        .def_prop_ro("center", [](const Bounds& b) { return from_vec3(b.center()); })
        .def_prop_ro("extent", [](const Bounds& b) { return from_vec3(b.extent()); })
        .def("__repr__", [](const Bounds& b) {
            auto t = [](Vec3 v) { return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")"; };
            return b.empty() ? std::string("<clvis.Bounds empty>") : "<clvis.Bounds " + t(b.lo) + " - " + t(b.hi) + ">";
        });
}

Mat4 transform_of(nb::handle transform)
{
    return transform.is_none() ? Mat4::identity() : to_mat4(transform, "Scene: transform");
}

std::size_t add_arrays(PyScene& s, nb::handle positions, nb::handle indices, nb::handle transform,
                       std::string name)
{
    auto p = as_host_array<float>(positions, {"Scene.add_mesh: positions", "(V, 3)", 2, 3, false}, "float32");
    auto i = as_host_array<std::uint32_t>(indices, {"Scene.add_mesh: indices", "(T, 3)", 2, 3, true}, "uint32");
    const Mat4 m = transform_of(transform);
    return unlocked(s.lock, [&] {
        return s.scene.add_mesh(p.data(), p.shape(0), i.data(), i.shape(0), m, std::move(name));
    });
}

void bind_scene_methods(nb::class_<PyScene>& c)
{
    c.def("add_mesh", &add_arrays,
          nb::sig("def add_mesh(self, positions: numpy.typing.ArrayLike, indices: numpy.typing.ArrayLike, "
                  "transform: numpy.typing.ArrayLike | None = None, name: str = '') -> int"),
          nb::arg("positions"), nb::arg("indices"), nb::arg("transform") = nb::none(),
          nb::arg("name") = "",
          "Adds a mesh from (V, 3) positions and (T, 3) vertex indices and returns its index.\n\n"
          "float32 positions and uint32 indices in C order are read as they are; other numeric\n"
          "dtypes and layouts are converted once (indices must be integers that fit 32 bits).\n"
          "`transform` is a (4, 4) object-to-world matrix applied to column vectors. The arrays\n"
          "are copied: changing them later does not change the scene.\n\n"
          "Example:\n    scene.add_mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), [[0, 1, 2]])");
    c.def(
        "add_mesh",
        [](PyScene& s, MeshData mesh, nb::handle transform) {
            const Mat4 m = transform_of(transform);
            return unlocked(s.lock, [&] { return s.scene.add_mesh(std::move(mesh), m); });
        },
        nb::sig("def add_mesh(self, mesh: Mesh, transform: numpy.typing.ArrayLike | None = None) -> int"),
        nb::arg("mesh"), nb::arg("transform") = nb::none(), "Adds a Mesh (copied) and returns its index.");
    c.def(
        "set_positions",
        [](PyScene& s, std::size_t mesh, nb::handle positions) {
            auto p = as_host_array<float>(positions, {"Scene.set_positions: positions", "(V, 3)", 2, 3, false}, "float32");
            unlocked(s.lock, [&] { s.scene.set_positions(mesh, p.data(), p.shape(0)); });
        },
        nb::sig("def set_positions(self, mesh: int, positions: numpy.typing.ArrayLike) -> None"),
        nb::arg("mesh"), nb::arg("positions"),
        "Replaces the positions of mesh `mesh` (same vertex count); renderers follow with update().");
    c.def(
        "set_transform",
        [](PyScene& s, std::size_t mesh, nb::handle transform) {
            const Mat4 m = to_mat4(transform, "Scene.set_transform: transform");
            unlocked(s.lock, [&] { s.scene.set_transform(mesh, m); });
        },
        nb::sig("def set_transform(self, mesh: int, transform: numpy.typing.ArrayLike) -> None"),
        nb::arg("mesh"), nb::arg("transform"), "Replaces the (4, 4) transform of mesh `mesh`.");
}

} // namespace

void bind_scene(nb::module_& m)
{
    bind_mesh(m);
    bind_bounds(m);
    nb::class_<PyScene> c(m, "Scene", nb::is_weak_referenceable(),
                          "Meshes of triangles; triangle ids run mesh after mesh in the order they are added.\n\n"
                          "Example:\n    scene = clvis.Scene()\n    scene.add_mesh(positions, indices)\n"
                          "    camera = clvis.Camera.framing(scene.bounds())");
    c.def(nb::init<>());
    bind_scene_methods(c);
    c.def("bounds", [](PyScene& s) { return unlocked(s.lock, [&] { return s.scene.bounds(); }); },
          "World-space bounds of every vertex (transforms applied).");
    c.def_prop_ro("triangle_count", [](PyScene& s) { return unlocked(s.lock, [&] { return s.scene.triangle_count(); }); });
    c.def_prop_ro("vertex_count", [](PyScene& s) { return unlocked(s.lock, [&] { return s.scene.vertex_count(); }); });
    c.def_prop_ro("mesh_count", [](PyScene& s) { return unlocked(s.lock, [&] { return s.scene.meshes().size(); }); });
    c.def("mesh_of", [](PyScene& s, std::uint32_t id) { return unlocked(s.lock, [&] { return s.scene.mesh_of(id); }); },
          nb::arg("id"), "The index of the mesh that holds triangle `id`.");
    c.def("__repr__", [](PyScene& s) {
        return unlocked(s.lock, [&] {
            return "<clvis.Scene: " + std::to_string(s.scene.meshes().size()) + " meshes, " +
                   std::to_string(s.scene.triangle_count()) + " triangles>";
        });
    });

    m.def(
        "load_scene", [](const std::filesystem::path& path) {
            auto s = std::make_unique<PyScene>();
            nb::gil_scoped_release nogil;
            s->scene = load_scene({path.string()});
            return s.release();
        },
        nb::arg("path"), nb::rv_policy::take_ownership,
        "Loads mesh files (or one .json scene file) into one Scene, in order.\n\n"
        "Example:\n    scene = clvis.load_scene(['scenes/spot.obj', 'scenes/teapot.obj'])");
    m.def(
        "load_scene",
        [](const std::vector<std::filesystem::path>& paths) {
            auto s = std::make_unique<PyScene>();
            std::vector<std::string> names(paths.begin(), paths.end());
            nb::gil_scoped_release nogil;
            s->scene = load_scene(names);
            return s.release();
        },
        nb::arg("paths"), nb::rv_policy::take_ownership);
}

} // namespace clvis::python
