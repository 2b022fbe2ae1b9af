// The per-sample kernels' scene (render/sample_scene.hpp): the expansion of a plain scene, or the
// visible triangles of a scene with instances, computed item by item as Scene::world_positions
// computes them (kernels/shared/instance.h) and renumbered in the keys.
#include "render/sample_scene.hpp"

#include "render/renderer_impl.hpp"
#include "scene/instance_transform.hpp"
#include "shared/visibility.h"

#include <algorithm>
#include <cmath>

namespace clvis::detail {

void world_normal(const Mat4& t, const float n[3], float out[3])
{
    // Cofactor matrix of the linear part: proportional to the inverse transpose.
    double a = t(0, 0), b = t(0, 1), c = t(0, 2), d = t(1, 0), e = t(1, 1), f = t(1, 2), g = t(2, 0), h = t(2, 1),
           k = t(2, 2);
    double cof[9] = {e * k - f * h, f * g - d * k, d * h - e * g, c * h - b * k, a * k - c * g,
                     b * g - a * h, b * f - c * e, c * d - a * f, a * e - b * d};
    double x = n[0], y = n[1], z = n[2];
    double w[3] = {cof[0] * x + cof[1] * y + cof[2] * z, cof[3] * x + cof[4] * y + cof[5] * z,
                   cof[6] * x + cof[7] * y + cof[8] * z};
    double len = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    for (int i = 0; i < 3; ++i) out[i] = len > 0 ? float(w[i] / len) : 0.0f;
}

namespace {

cl::Buffer upload(Renderer::Impl& r, const void* data, std::size_t bytes)
{
    cl::Buffer b(r.dev().context, CL_MEM_READ_ONLY, std::max<std::size_t>(bytes, 16));
    if (bytes) r.queue.enqueueWriteBuffer(b, CL_TRUE, 0, bytes, data);
    return b;
}

} // namespace

SampleScene sample_scene(Renderer::Impl& r, const VisibilityBuffer& vis, bool geometry)
{
    SampleScene out;
    if (!r.instanced) {
        out.scene = r.scene_buffers();
        out.keys = cl::Buffer(vis.keys(), true);
        return out;
    }
    const Scene& scene = r.scene;
    bool normals = false;
    for (std::size_t item = 0; item < scene.meshes().size(); ++item) normals |= !scene.data_of(item).normals.empty();
    if (!geometry) {
        float none[4] = {0, 0, 0, 0};
        out.scene.positions = upload(r, none, sizeof none);
        out.scene.indices = upload(r, none, sizeof none);
        out.scene.normals = upload(r, none, sizeof none);
        out.scene.has_normals = normals;
        out.scene.triangle_count = std::uint32_t(scene.triangle_count());
        out.keys = cl::Buffer(vis.keys(), true);
        return out;
    }
    std::vector<std::uint64_t> keys = vis.read_keys();
    std::vector<std::uint32_t> ids;
    ids.reserve(keys.size());
    for (std::uint64_t key : keys) {
        std::uint32_t id = std::uint32_t(key);
        if (id < scene.triangle_count()) ids.push_back(id);
    }
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    // Each visible triangle's three corners as the expansion holds them.
    std::vector<float> positions(ids.size() * 9), world_normals(normals ? ids.size() * 9 : 0, 0.0f);
    std::vector<std::uint32_t> indices(ids.size() * 3);
    for (std::size_t i = 0; i < ids.size(); ++i) {
        std::size_t item = scene.mesh_of(ids[i]);
        const Scene::Mesh& m = scene.meshes()[item];
        const MeshData& data = scene.data_of(item);
        std::size_t local = ids[i] - m.first_triangle;
        for (std::size_t k = 0; k < 3; ++k) {
            std::uint32_t v = data.indices[local * 3 + k];
            transform_positions(m.transform, &data.positions[std::size_t(v) * 3], 1, &positions[i * 9 + k * 3]);
            if (normals && !data.normals.empty())
                world_normal(m.transform, &data.normals[std::size_t(v) * 3], &world_normals[i * 9 + k * 3]);
            indices[i * 3 + k] = std::uint32_t(i * 3 + k);
        }
        for (std::size_t c = 0; c < 9; ++c)
            if (!std::isfinite(positions[i * 9 + c]))
                throw Error(Error::Kind::InvalidArgument,
                            "mesh '" + data.name + "': a transformed vertex overflows float32");
    }
    // Ids renumbered into the visible triangles; the depth bits stay.
    for (std::uint64_t& key : keys) {
        std::uint32_t id = std::uint32_t(key);
        std::uint32_t renumbered = CLVIS_BACKGROUND_ID;
        if (id < scene.triangle_count())
            renumbered = std::uint32_t(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin());
        key = (key & ~std::uint64_t(0xFFFFFFFFu)) | renumbered;
    }
    out.scene.positions = upload(r, positions.data(), positions.size() * 4);
    out.scene.indices = upload(r, indices.data(), indices.size() * 4);
    out.scene.normals = upload(r, world_normals.data(), world_normals.size() * 4);
    out.scene.has_normals = normals;
    out.scene.triangle_count = std::uint32_t(ids.size());
    out.scene.vertex_count = std::uint32_t(ids.size() * 3);
    out.keys = upload(r, keys.data(), keys.size() * 8);
    r.queue.finish(); // the host arrays go out of scope
    return out;
}

} // namespace clvis::detail
