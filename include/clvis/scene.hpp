// Scenes: items of triangles, concatenated in the order they are added: meshes, each with an
// optional 4x4 transform, and instances (a prototype mesh, stored once, and a transform). Triangle
// ids follow CONVENTIONS.md: item after item, as if each instance were written out as its own
// mesh; faces in file order, polygons fanned (v0, vk, vk+1), nothing reordered, merged or dropped.
// A Scene lives on the host; a Renderer uploads it.
#pragma once

#include <clvis/math.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace clvis {

/// The background id of every id buffer (no triangle at that sample).
constexpr std::uint32_t background_id = 0xFFFFFFFFu;
/// The most triangles a scene may hold: ids are 32-bit and background_id is reserved.
constexpr std::uint64_t max_triangles = 0xFFFFFFFFull;

/// A face-varying vertex attribute (CONVENTIONS.md "Vertex attributes"): one value per corner of
/// every triangle, so seams need no split vertices. The loaders name them "uv" (OBJ vt, PLY u/v,
/// glTF TEXCOORD_0), "uv1" (glTF TEXCOORD_1), "color" (RGBA) or by a PLY property's own name.
struct CornerAttribute {
    std::string name;          ///< unique within a mesh; letters, digits and '_'
    int components = 1;        ///< 1 to 4
    std::vector<float> values; ///< components floats per corner, corners in index order: 3 per triangle

    std::size_t corner_count() const { return components > 0 ? values.size() / std::size_t(components) : 0; }
};

/// One mesh as plain arrays: positions x,y,z per vertex, three indices per triangle.
struct MeshData {
    std::string name;               ///< for messages (a file name, "sphere", ...)
    std::vector<float> positions;   ///< 3 floats per vertex
    std::vector<std::uint32_t> indices; ///< 3 per triangle, each < vertex count
    std::vector<float> normals;     ///< optional: 3 floats per vertex, or empty
    std::vector<CornerAttribute> attributes; ///< optional, face-varying; never change ids or depths

    std::size_t vertex_count() const { return positions.size() / 3; }
    std::size_t triangle_count() const { return indices.size() / 3; }
};

class Scene {
public:
    /// `prototype` of an item that is a plain mesh.
    static constexpr std::size_t no_prototype = std::size_t(-1);

    /// One item: a mesh, or an instance of a prototype (then `data` is empty: see data_of).
    struct Mesh {
        MeshData data;
        Mat4 transform;                 ///< object -> world, applied to positions only
        std::uint32_t first_triangle = 0; ///< id of this item's first triangle
        std::size_t prototype = no_prototype; ///< index into prototypes(), or no_prototype
    };

    /// Adds a mesh and returns its index. Throws Error(InvalidArgument) naming the mesh and the
    /// element for an index out of range, a non-finite position, a size that is not a multiple
    /// of 3, or a transform that is not affine or not finite; Error(Limit) past max_triangles.
    std::size_t add_mesh(MeshData mesh, const Mat4& transform = Mat4::identity());
    /// The same from spans of memory (copied).
    std::size_t add_mesh(const float* positions, std::size_t vertex_count,
                         const std::uint32_t* indices, std::size_t triangle_count,
                         const Mat4& transform = Mat4::identity(), std::string name = {});

    /// Stores a mesh once for instances; it gets no ids of its own. Returns its index in
    /// prototypes(). Checked as add_mesh checks a mesh.
    std::size_t add_prototype(MeshData mesh);
    /// Adds an instance of prototype `prototype` as the next item (its ids follow the items
    /// before it) and returns its item index in meshes(). Error(InvalidArgument) for a prototype
    /// that does not exist or a transform add_mesh would refuse; Error(Limit) past max_triangles.
    /// The prototype is stored once on the host, and on the device by the ray and raster paths;
    /// shading, resolve and AO and shadow rays upload only the triangles a buffer shows,
    /// bounds(), triangle() and the referees read the items, and so do Path::Brute and ray
    /// queries with brute set (the meshes once and a record per item on the device): nothing
    /// builds the expansion (world_positions).
    std::size_t add_instance(std::size_t prototype, const Mat4& transform);

    /// Replaces the positions of mesh `mesh` (same vertex count): animation. Renderers that
    /// were made from this scene pick the change up with Renderer::update().
    void set_positions(std::size_t mesh, const float* positions, std::size_t vertex_count);
    /// Moves item `mesh`, a mesh or an instance.
    void set_transform(std::size_t mesh, const Mat4& transform);

    const std::vector<Mesh>& meshes() const { return meshes_; }
    const std::vector<MeshData>& prototypes() const { return prototypes_; }
    /// The triangles of item `mesh`: its own data, or its prototype's.
    const MeshData& data_of(std::size_t mesh) const;
    std::size_t triangle_count() const { return triangle_count_; }
    std::size_t vertex_count() const { return vertex_count_; }
    bool empty() const { return triangle_count_ == 0; }

    /// World-space bounds of every vertex referenced or not (transforms applied): the bounds of
    /// world_positions(), computed item by item without it.
    Bounds bounds() const;

    /// World-space positions of every vertex, meshes concatenated (float32, transforms applied
    /// by kernels/shared/instance.h). Computed on demand and cached until the next
    /// change: the whole expansion, so nothing in the library calls it for a scene with
    /// instances (the bench's Embree and llvmpipe references do).
    const std::vector<float>& world_positions() const;
    /// Indices into world_positions(), 3 per triangle, in id order.
    const std::vector<std::uint32_t>& world_indices() const;
    /// The world-space vertices of triangle `id` (9 floats): world_positions()'s bits, computed
    /// from its item without the expansion.
    void triangle(std::uint32_t id, float out[9]) const;
    /// Which mesh holds triangle `id`.
    std::size_t mesh_of(std::uint32_t id) const;

private:
    void invalidate();
    std::size_t mesh_of_vertex(std::size_t vertex) const;

    std::size_t add_item(Mesh item, const std::string& name);

    std::vector<Mesh> meshes_;
    std::vector<MeshData> prototypes_;
    std::size_t triangle_count_ = 0;
    std::size_t vertex_count_ = 0;
    mutable std::vector<float> world_positions_;
    mutable std::vector<std::uint32_t> world_indices_;
    mutable bool world_valid_ = false;
};

} // namespace clvis
