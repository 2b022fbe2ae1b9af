// Scenes from Python: meshes from NumPy arrays (one conversion where a dtype or layout differs,
// then copied into the scene), from files (clvis.load_mesh, clvis.load_scene, glTF instances
// included) or procedural; prototypes and their instances; bounds; positions and transforms
// changed for Renderer.update.
#include "arrays.hpp"

#include <nanobind/stl/array.h>
#include <nanobind/stl/filesystem.h>
#include <nanobind/stl/optional.h>
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
        .def(
            "set_attribute",
            [](MeshData& d, const std::string& name, nb::handle values) {
                // (3T, C): one row per corner, corners in index order (CONVENTIONS.md "Vertex attributes").
                auto v = as_host_array<float>(values, {"Mesh.set_attribute: values", "(3T, C)", 2, 0, false}, "float32");
                CornerAttribute a{name, int(v.shape(1)), std::vector<float>(v.data(), v.data() + v.size())};
                for (CornerAttribute& old : d.attributes)
                    if (old.name == name) return void(old = std::move(a));
                d.attributes.push_back(std::move(a));
            },
            nb::sig("def set_attribute(self, name: str, values: numpy.typing.ArrayLike) -> None"), nb::arg("name"),
            nb::arg("values"),
            "Sets the face-varying attribute `name` ('uv', 'color', any name): a (3T, C) float32 array, one\n"
            "row of C (1 to 4) components per corner of every triangle in index order; checked when the mesh\n"
            "is added to a Scene. Renderer.resolve(v, [name]) interpolates it per pixel.")
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

/// A MeshData from (V, 3) positions and (T, 3) indices (converted once where needed), for `what`.
MeshData mesh_of_arrays(nb::handle positions, nb::handle indices, std::string name, const std::string& what)
{
    const std::string pn = what + ": positions", in = what + ": indices";
    auto p = as_host_array<float>(positions, {pn.c_str(), "(V, 3)", 2, 3, false}, "float32");
    auto i = as_host_array<std::uint32_t>(indices, {in.c_str(), "(T, 3)", 2, 3, true}, "uint32");
    MeshData mesh;
    mesh.name = std::move(name);
    mesh.positions.assign(p.data(), p.data() + p.size());
    mesh.indices.assign(i.data(), i.data() + i.size());
    return mesh;
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

/// The item's prototype, or None for a plain mesh; Error(InvalidArgument) for no such item.
std::optional<std::size_t> prototype_of(PyScene& s, std::size_t item)
{
    return unlocked(s.lock, [&]() -> std::optional<std::size_t> {
        if (item >= s.scene.meshes().size())
            throw Error(Error::Kind::InvalidArgument, "Scene.prototype_of: no item " + std::to_string(item) + " (the scene has " +
                                                          std::to_string(s.scene.meshes().size()) + ")");
        const std::size_t p = s.scene.meshes()[item].prototype;
        return p == Scene::no_prototype ? std::nullopt : std::optional<std::size_t>(p);
    });
}

void bind_instances(nb::class_<PyScene>& c)
{
    c.def(
        "add_prototype",
        [](PyScene& s, nb::handle positions, nb::handle indices, std::string name) {
            MeshData mesh = mesh_of_arrays(positions, indices, std::move(name), "Scene.add_prototype");
            return unlocked(s.lock, [&] { return s.scene.add_prototype(std::move(mesh)); });
        },
        nb::sig("def add_prototype(self, positions: numpy.typing.ArrayLike, indices: numpy.typing.ArrayLike, "
                "name: str = '') -> int"),
        nb::arg("positions"), nb::arg("indices"), nb::arg("name") = "",
        "Stores a mesh once for instances (arrays as add_mesh takes them, copied) and returns its index\n"
        "among the prototypes. A prototype has no triangle ids of its own: each add_instance adds its\n"
        "triangles as the next item, as if the mesh were added with that transform.\n\n"
        "Example:\n    tree = scene.add_prototype(positions, indices)\n"
        "    for x in range(10):\n        scene.add_instance(tree, np.diag([1.0, 1, 1, 1]) + np.eye(4, k=3) * x)");
    c.def(
        "add_prototype",
        [](PyScene& s, MeshData mesh) { return unlocked(s.lock, [&] { return s.scene.add_prototype(std::move(mesh)); }); },
        nb::arg("mesh"), "Stores a Mesh (copied) as a prototype and returns its index.");
    c.def(
        "add_instance",
        [](PyScene& s, std::size_t prototype, nb::handle transform) {
            const Mat4 m = transform_of(transform);
            return unlocked(s.lock, [&] { return s.scene.add_instance(prototype, m); });
        },
        nb::sig("def add_instance(self, prototype: int, transform: numpy.typing.ArrayLike | None = None) -> int"),
        nb::arg("prototype"), nb::arg("transform") = nb::none(),
        "Adds an instance of prototype `prototype` with a (4, 4) object-to-world transform as the next\n"
        "item and returns its item index (for set_transform, mesh_of). Its ids follow the items before it.");
    c.def_prop_ro("prototype_count", [](PyScene& s) { return unlocked(s.lock, [&] { return s.scene.prototypes().size(); }); },
                  "Prototypes stored (add_prototype, or a glTF mesh used by several nodes).");
    c.def("prototype_of", &prototype_of, nb::arg("item"),
          "The prototype that item `item` instances, or None for a plain mesh.");
    c.def(
        "transform",
        [](PyScene& s, std::size_t item) {
            const Mat4 m = unlocked(s.lock, [&] {
                if (item >= s.scene.meshes().size())
                    throw Error(Error::Kind::InvalidArgument, "Scene.transform: no item " + std::to_string(item));
                return s.scene.meshes()[item].transform;
            });
            return from_mat4(m);
        },
        nb::arg("item"), "The (4, 4) object-to-world transform of item `item` (a mesh or an instance).");
}

void bind_scene_methods(nb::class_<PyScene>& c)
{
    // The Mesh overload first: add_mesh(mesh, transform) with the transform positional reaches it.
    c.def(
        "add_mesh",
        [](PyScene& s, MeshData mesh, nb::handle transform) {
            const Mat4 m = transform_of(transform);
            return unlocked(s.lock, [&] { return s.scene.add_mesh(std::move(mesh), m); });
        },
        nb::sig("def add_mesh(self, mesh: Mesh, transform: numpy.typing.ArrayLike | None = None) -> int"),
        nb::arg("mesh"), nb::arg("transform") = nb::none(), "Adds a Mesh (copied) and returns its index.");
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
    bind_instances(c);
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
