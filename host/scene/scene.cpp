// The host scene: items in order (meshes, and instances of prototypes stored once), validated on
// entry, flattened to world space on demand. Ids are the concatenation of the items' triangles, as
// CONVENTIONS.md says, so an instanced scene flattens to the bits of its expansion; transformed
// vertices are computed in float32 by kernels/shared/instance.h, as the kernels compute them.
#include <clvis/error.hpp>
#include <clvis/scene.hpp>

#include "scene/instance_transform.hpp"
#include "scene/scene_probe.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

namespace clvis {

std::atomic<std::uint64_t> detail::expansion_vertices_built{0};

namespace {

[[noreturn]] void invalid(const std::string& mesh, const std::string& message)
{
    throw Error(Error::Kind::InvalidArgument, "mesh '" + mesh + "': " + message);
}

void check_transform(const std::string& name, const Mat4& t)
{
    for (double v : t.m)
        if (!std::isfinite(v)) invalid(name, "transform has a non-finite entry");
    if (t(3, 0) != 0 || t(3, 1) != 0 || t(3, 2) != 0 || t(3, 3) != 1)
        invalid(name, "transform's last row must be 0 0 0 1");
}

void check_positions(const std::string& name, const float* p, std::size_t vertex_count)
{
    for (std::size_t i = 0; i < vertex_count * 3; ++i)
        if (!std::isfinite(p[i]))
            invalid(name, "vertex " + std::to_string(i / 3) + " has a non-finite coordinate");
}

void check_mesh(const std::string& name, const MeshData& mesh)
{
    if (mesh.positions.size() % 3) invalid(name, "positions must hold 3 floats per vertex");
    if (mesh.indices.size() % 3) invalid(name, "indices must hold 3 per triangle");
    if (!mesh.normals.empty() && mesh.normals.size() != mesh.positions.size())
        invalid(name, "normals must be empty or one per vertex");
    for (std::size_t a = 0; a < mesh.attributes.size(); ++a) {
        const CornerAttribute& attr = mesh.attributes[a];
        std::string what = "attribute '" + attr.name + "'";
        if (attr.name.empty()) invalid(name, "attribute " + std::to_string(a) + " has no name");
        for (char c : attr.name)
            if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
                invalid(name, what + ": a name holds letters, digits and '_' only");
        for (std::size_t b = 0; b < a; ++b)
            if (mesh.attributes[b].name == attr.name) invalid(name, what + " appears twice");
        if (attr.components < 1 || attr.components > 4)
            invalid(name, what + " has " + std::to_string(attr.components) + " components (1 to 4)");
        if (attr.values.size() != mesh.indices.size() * std::size_t(attr.components))
            invalid(name, what + " holds " + std::to_string(attr.values.size()) + " floats, not " +
                              std::to_string(attr.components) + " per corner of " +
                              std::to_string(mesh.triangle_count()) + " triangles");
    }
    std::size_t vertices = mesh.vertex_count();
    check_positions(name, mesh.positions.data(), vertices);
    for (std::size_t i = 0; i < mesh.indices.size(); ++i)
        if (mesh.indices[i] >= vertices)
            invalid(name, "triangle " + std::to_string(i / 3) + " refers to vertex " +
                              std::to_string(mesh.indices[i]) + " of " + std::to_string(vertices));
}

} // namespace

std::size_t Scene::add_item(Mesh item, const std::string& name)
{
    const MeshData& data = item.prototype == no_prototype ? item.data : prototypes_[item.prototype];
    check_transform(name, item.transform);
    std::uint64_t total = std::uint64_t(triangle_count_) + data.triangle_count();
    if (total > max_triangles)
        throw Error(Error::Kind::Limit, "mesh '" + name + "': the scene would hold " + std::to_string(total) +
                                            " triangles, more than 32-bit ids allow (" +
                                            std::to_string(max_triangles) + ")");
    item.first_triangle = std::uint32_t(triangle_count_);
    triangle_count_ += data.triangle_count();
    vertex_count_ += data.vertex_count();
    meshes_.push_back(std::move(item));
    invalidate();
    return meshes_.size() - 1;
}

std::size_t Scene::add_mesh(MeshData mesh, const Mat4& transform)
{
    std::string name = mesh.name.empty() ? ("#" + std::to_string(meshes_.size())) : mesh.name;
    check_mesh(name, mesh);
    if (mesh.name.empty()) mesh.name = name;
    Mesh m;
    m.transform = transform;
    m.data = std::move(mesh);
    return add_item(std::move(m), name);
}

std::size_t Scene::add_prototype(MeshData mesh)
{
    std::string name = mesh.name.empty() ? ("prototype #" + std::to_string(prototypes_.size())) : mesh.name;
    check_mesh(name, mesh);
    if (mesh.name.empty()) mesh.name = name;
    prototypes_.push_back(std::move(mesh));
    return prototypes_.size() - 1;
}

std::size_t Scene::add_instance(std::size_t prototype, const Mat4& transform)
{
    if (prototype >= prototypes_.size())
        throw Error(Error::Kind::InvalidArgument, "Scene::add_instance: no prototype " + std::to_string(prototype) +
                                                      " (the scene has " + std::to_string(prototypes_.size()) + ")");
    Mesh m;
    m.transform = transform;
    m.prototype = prototype;
    return add_item(std::move(m), prototypes_[prototype].name + " instance " + std::to_string(meshes_.size()));
}

const MeshData& Scene::data_of(std::size_t mesh) const
{
    if (mesh >= meshes_.size())
        throw Error(Error::Kind::InvalidArgument, "Scene::data_of: no mesh " + std::to_string(mesh));
    const Mesh& m = meshes_[mesh];
    return m.prototype == no_prototype ? m.data : prototypes_[m.prototype];
}

std::size_t Scene::add_mesh(const float* positions, std::size_t vertex_count, const std::uint32_t* indices,
                            std::size_t triangle_count, const Mat4& transform, std::string name)
{
    if ((!positions && vertex_count) || (!indices && triangle_count))
        throw Error(Error::Kind::InvalidArgument, "Scene::add_mesh: null array with a non-zero count");
    // Refuse what ids cannot hold before copying anything.
    if (triangle_count > max_triangles || std::uint64_t(triangle_count_) + triangle_count > max_triangles)
        throw Error(Error::Kind::Limit, "mesh '" + name + "': the scene would hold " +
                                            std::to_string(std::uint64_t(triangle_count_) + triangle_count) +
                                            " triangles, more than 32-bit ids allow (" + std::to_string(max_triangles) + ")");
    MeshData m;
    m.name = std::move(name);
    m.positions.assign(positions, positions + vertex_count * 3);
    m.indices.assign(indices, indices + triangle_count * 3);
    return add_mesh(std::move(m), transform);
}

void Scene::set_positions(std::size_t mesh, const float* positions, std::size_t vertex_count)
{
    if (mesh >= meshes_.size())
        throw Error(Error::Kind::InvalidArgument, "Scene::set_positions: no mesh " + std::to_string(mesh));
    Mesh& m = meshes_[mesh];
    if (m.prototype != no_prototype)
        invalid(data_of(mesh).name, "set_positions on item " + std::to_string(mesh) +
                                        ", an instance: its prototype's positions are shared");
    if (vertex_count != m.data.vertex_count())
        invalid(m.data.name, "set_positions got " + std::to_string(vertex_count) + " vertices, the mesh has " +
                                 std::to_string(m.data.vertex_count()));
    check_positions(m.data.name, positions, vertex_count);
    std::copy(positions, positions + vertex_count * 3, m.data.positions.begin());
    invalidate();
}

void Scene::set_transform(std::size_t mesh, const Mat4& transform)
{
    if (mesh >= meshes_.size())
        throw Error(Error::Kind::InvalidArgument, "Scene::set_transform: no mesh " + std::to_string(mesh));
    check_transform(data_of(mesh).name, transform);
    meshes_[mesh].transform = transform;
    invalidate();
}

namespace {

/// Error(InvalidArgument) as world_positions gives it for an item whose float32 world vertex overflows.
[[noreturn]] void overflows(const std::string& mesh)
{
    throw Error(Error::Kind::InvalidArgument, "mesh '" + mesh + "': a transformed vertex overflows float32");
}

} // namespace

void Scene::invalidate() { world_valid_ = false; }

const std::vector<float>& Scene::world_positions() const
{
    if (!world_valid_) {
        world_positions_.resize(vertex_count_ * 3);
        world_indices_.resize(triangle_count_ * 3);
        std::size_t v = 0, t = 0;
        for (std::size_t k = 0; k < meshes_.size(); ++k) {
            const Mesh& m = meshes_[k];
            const MeshData& data = data_of(k);
            detail::transform_positions(m.transform, data.positions.data(), data.vertex_count(),
                                        &world_positions_[v * 3]);
            for (std::uint32_t index : data.indices) world_indices_[t++] = index + std::uint32_t(v);
            v += data.vertex_count();
        }
        for (std::size_t i = 0; i < world_positions_.size(); ++i)
            if (!std::isfinite(world_positions_[i])) overflows(data_of(mesh_of_vertex(i / 3)).name);
        world_valid_ = true;
        for (const Mesh& m : meshes_)
            if (m.prototype != no_prototype) {
                detail::expansion_vertices_built += vertex_count_; // an expansion of instances
                break;
            }
    }
    return world_positions_;
}

std::size_t Scene::mesh_of_vertex(std::size_t vertex) const
{
    std::size_t first = 0;
    for (std::size_t i = 0; i < meshes_.size(); ++i) {
        first += data_of(i).vertex_count();
        if (vertex < first) return i;
    }
    return meshes_.size() - 1;
}

const std::vector<std::uint32_t>& Scene::world_indices() const
{
    world_positions();
    return world_indices_;
}

Bounds Scene::bounds() const
{
    // Item by item, a block of world vertices at a time: the bits world_positions() would hold,
    // without the expansion (a scene of many instances need not fit expanded).
    Bounds b;
    constexpr std::size_t block = 4096;
    float w[block * 3];
    for (std::size_t k = 0; k < meshes_.size(); ++k) {
        const MeshData& data = data_of(k);
        for (std::size_t v = 0; v < data.vertex_count(); v += block) {
            std::size_t n = std::min(block, data.vertex_count() - v);
            detail::transform_positions(meshes_[k].transform, &data.positions[v * 3], n, w);
            for (std::size_t i = 0; i < n * 3; i += 3) {
                if (!std::isfinite(w[i]) || !std::isfinite(w[i + 1]) || !std::isfinite(w[i + 2]))
                    overflows(data.name);
                b.add(Vec3{w[i], w[i + 1], w[i + 2]});
            }
        }
    }
    return b;
}

void Scene::triangle(std::uint32_t id, float out[9]) const
{
    if (id >= triangle_count_)
        throw Error(Error::Kind::InvalidArgument, "Scene::triangle: no triangle " + std::to_string(id));
    // The item's own vertices through its transform: world_positions()'s bits, nothing expanded.
    std::size_t item = mesh_of(id);
    const MeshData& data = data_of(item);
    std::size_t local = id - meshes_[item].first_triangle;
    for (int k = 0; k < 3; ++k) {
        std::uint32_t v = data.indices[local * 3 + std::size_t(k)];
        detail::transform_positions(meshes_[item].transform, &data.positions[std::size_t(v) * 3], 1, &out[k * 3]);
        if (!std::isfinite(out[k * 3]) || !std::isfinite(out[k * 3 + 1]) || !std::isfinite(out[k * 3 + 2]))
            overflows(data.name);
    }
}

std::size_t Scene::mesh_of(std::uint32_t id) const
{
    if (id >= triangle_count_)
        throw Error(Error::Kind::InvalidArgument, "Scene::mesh_of: no triangle " + std::to_string(id));
    auto it = std::upper_bound(meshes_.begin(), meshes_.end(), id,
                               [](std::uint32_t v, const Mesh& m) { return v < m.first_triangle; });
    return std::size_t(it - meshes_.begin()) - 1;
}

} // namespace clvis
