// The device description of a scene with instances (frame/instanced_scene.hpp): prototypes and
// plain meshes once, a clvis_item per item.
#include "frame/instanced_scene.hpp"

#include "runtime/cl_runtime.hpp"
#include "scene/instance_transform.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace clvis::detail {

namespace {

/// Appends `data`'s indices and positions (world: `positions`) as a mesh record.
clvis_item_mesh add_mesh(const MeshData& data, const float* positions, std::vector<float>& all_positions,
                         std::vector<std::uint32_t>& all_indices)
{
    if (all_positions.size() / 3 + data.vertex_count() > 0xFFFFFFFFull ||
        all_indices.size() / 3 + data.triangle_count() > 0xFFFFFFFFull)
        throw Error(Error::Kind::Limit, "the scene's meshes hold more than 2^32 vertices or triangles");
    clvis_item_mesh m{std::uint32_t(all_positions.size() / 3), std::uint32_t(data.vertex_count()),
                      std::uint32_t(all_indices.size() / 3), std::uint32_t(data.triangle_count())};
    all_positions.insert(all_positions.end(), positions, positions + data.positions.size());
    all_indices.insert(all_indices.end(), data.indices.begin(), data.indices.end());
    return m;
}

/// Error(InvalidArgument) as Scene::world_positions gives it when an instance's float32 vertices
/// overflow: the world box of the prototype's box first, each vertex only when that is not finite.
void check_finite(const MeshData& proto, const float lo[3], const float hi[3], const std::array<float, 12>& m)
{
    float wlo[3], whi[3];
    clvis_instance_box(m.data(), lo, hi, wlo, whi);
    bool finite = true;
    for (int a = 0; a < 3; ++a) finite &= std::isfinite(wlo[a]) && std::isfinite(whi[a]);
    if (finite) return;
    for (std::size_t i = 0; i < proto.positions.size(); i += 3) {
        clvis_vec3 w = clvis_instance_point(m.data(), proto.positions[i], proto.positions[i + 1], proto.positions[i + 2]);
        if (!std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z))
            throw Error(Error::Kind::InvalidArgument, "mesh '" + proto.name + "': a transformed vertex overflows float32");
    }
}

} // namespace

void InstancedScene::upload(const Scene& scene, Device::Impl& device, cl::CommandQueue& queue)
{
    std::vector<float> positions;
    std::vector<std::uint32_t> indices;
    host_meshes.clear();
    host_items.clear();
    std::vector<std::array<float, 6>> boxes; // each prototype's object-space box
    for (const MeshData& proto : scene.prototypes()) {
        host_meshes.push_back(add_mesh(proto, proto.positions.data(), positions, indices));
        std::array<float, 6> b{INFINITY, INFINITY, INFINITY, -INFINITY, -INFINITY, -INFINITY};
        for (std::size_t i = 0; i < proto.positions.size(); ++i) {
            b[i % 3] = std::min(b[i % 3], proto.positions[i]);
            b[3 + i % 3] = std::max(b[3 + i % 3], proto.positions[i]);
        }
        boxes.push_back(b);
    }
    std::uint64_t vertices = 0;
    std::vector<float> world;
    for (std::size_t k = 0; k < scene.meshes().size(); ++k) {
        const Scene::Mesh& item = scene.meshes()[k];
        const MeshData& data = scene.data_of(k);
        if (data.triangle_count() == 0) continue;
        clvis_item rec{};
        rec.first_id = item.first_triangle;
        rec.vertex_lo = std::uint32_t(vertices);
        rec.vertex_hi = std::uint32_t(vertices >> 32);
        auto m = instance_matrix(item.transform);
        if (item.prototype == Scene::no_prototype) {
            world.resize(data.positions.size());
            transform_positions(item.transform, data.positions.data(), data.vertex_count(), world.data());
            for (float f : world)
                if (!std::isfinite(f))
                    throw Error(Error::Kind::InvalidArgument, "mesh '" + data.name + "': a transformed vertex overflows float32");
            rec.mesh = std::uint32_t(host_meshes.size());
            host_meshes.push_back(add_mesh(data, world.data(), positions, indices));
        } else {
            const auto& b = boxes[item.prototype];
            check_finite(data, &b[0], &b[3], m);
            rec.mesh = std::uint32_t(item.prototype) | (item.transform.is_identity() ? 0u : CLVIS_ITEM_TRANSFORMED);
        }
        std::copy(m.begin(), m.end(), rec.m);
        host_items.push_back(rec);
        vertices += data.vertex_count();
    }
    triangle_count = std::uint32_t(scene.triangle_count());
    auto make = [&](cl::Buffer& buffer, const void* data, std::size_t bytes, const char* what) {
        std::size_t size = std::max<std::size_t>(bytes, 16);
        device.check_allocation(size, std::string("the scene's ") + what);
        buffer = cl::Buffer(device.context, CL_MEM_READ_ONLY, size);
        if (bytes) queue.enqueueWriteBuffer(buffer, CL_FALSE, 0, bytes, data);
        device_bytes += size;
    };
    device_bytes = 0;
    try {
        make(this->positions, positions.data(), positions.size() * 4, "mesh vertices");
        make(this->indices, indices.data(), indices.size() * 4, "mesh triangles");
        make(meshes, host_meshes.data(), host_meshes.size() * sizeof(clvis_item_mesh), "meshes");
        make(items, host_items.data(), host_items.size() * sizeof(clvis_item), "instances");
        queue.finish();
    } catch (const cl::Error& e) {
        throw_cl_error(e, "uploading the scene's meshes and instances to " + device.info.name);
    }
}

std::vector<ItemChunk> InstancedScene::chunks(std::size_t triangles) const
{
    triangles = std::min<std::size_t>(std::max<std::size_t>(triangles, 1), 0xFFFFFFFFu);
    std::vector<ItemChunk> out;
    ItemChunk c;
    std::uint64_t chunk_vertices = 0;
    for (std::uint32_t i = 0; i < host_items.size(); ++i) {
        const clvis_item_mesh& mesh = host_meshes[host_items[i].mesh & ~CLVIS_ITEM_TRANSFORMED];
        bool full = std::uint64_t(c.triangle_count) + mesh.triangle_count > triangles ||
                    chunk_vertices + mesh.vertex_count > 3 * std::uint64_t(triangles);
        if (c.end_item > c.first_item && full) {
            out.push_back(c);
            c = ItemChunk{i, i, host_items[i].first_id, 0, 0};
            chunk_vertices = 0;
        }
        if (c.end_item == c.first_item) c = ItemChunk{i, i, host_items[i].first_id, 0, 0};
        c.end_item = i + 1;
        c.triangle_count += mesh.triangle_count;
        chunk_vertices += mesh.vertex_count;
        c.vertex_count = std::uint32_t(chunk_vertices);
    }
    if (c.end_item > c.first_item) out.push_back(c);
    return out;
}

} // namespace clvis::detail
