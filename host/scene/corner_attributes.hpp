// What the mesh loaders share to fill MeshData::attributes (CONVENTIONS.md "Vertex attributes"):
// values read per vertex (PLY, glTF, OBJ colours) expanded to one value per corner through the
// triangles' indices, names made of letters, digits and '_', and the attributes of several meshes
// put end to end (a glTF scene flattened into one mesh). Nothing here allocates for a file that
// has no attributes.
#pragma once

#include <clvis/scene.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace clvis::detail {

/// An attribute as a file stores it: `components` floats per vertex.
struct VertexAttribute {
    std::string name;
    int components = 1;
    std::vector<float> values; ///< components per vertex, in vertex order
};

/// The corners of `indices` (3 per triangle, in index order) given the values of their vertices.
/// Every index must be below the vertex count of `a` (the loaders check indices first).
CornerAttribute corners_of(const VertexAttribute& a, const std::vector<std::uint32_t>& indices);

/// `name` with every character that is not a letter, digit or '_' replaced by '_' (so that a
/// PLY property "temp-C" becomes the attribute "temp_C").
std::string attribute_name(std::string_view name);

/// The attributes of meshes placed end to end (their triangles concatenated in this order): the
/// union of their names in order of first appearance, with NaN corners for a mesh that lacks one.
/// A name met with two different component counts takes the larger (missing components NaN).
/// Empty when no mesh has attributes.
std::vector<CornerAttribute> concatenate_attributes(const std::vector<const MeshData*>& meshes);

/// A vertex property of a PLY header, as plan_ply_attributes sees it.
struct PlyVertexProperty {
    std::string_view name;
    bool list = false;
    double integer_max = 0; ///< the largest value of its integer type, 0 for float and double
};

/// Where each vertex property of a PLY file goes among the attributes.
struct PlyAttributePlan {
    struct Slot {
        int attribute = -1;  ///< index into attributes, -1: not an attribute (x, y, z, nx, ny, nz, lists)
        int component = 0;
        double divisor = 1;  ///< colours of an integer type: the type's maximum
    };
    std::vector<VertexAttribute> attributes; ///< values sized for every vertex (alpha 1 preset)
    std::vector<Slot> slots;                 ///< one per property, in header order
};

/// The attributes of a PLY vertex element of `vertices` vertices: "uv" from `u, v`, `s, t` or
/// `texture_u, texture_v` (the first pair present), "color" from `red, green, blue[, alpha]`
/// (integers divided by their type's maximum, alpha 1 when absent), and every other scalar
/// property but x, y, z, nx, ny, nz by its own name (attribute_name), one component. List
/// properties are skipped. Error(Io) "<file>: ..." when two properties would give one name.
PlyAttributePlan plan_ply_attributes(const std::vector<PlyVertexProperty>& properties, std::uint64_t vertices,
                                     const std::string& file);

} // namespace clvis::detail
