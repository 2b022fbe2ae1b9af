// Flow between two views (include/clvis/flow.hpp, kernels/flow.cl) on the Renderer's queue: the
// corners of the triangles at each view, as the resident expansion (a plain scene whose items stay)
// or placed on the host for only the triangles view A shows (instances, or items that move), as
// render/sample_scene.cpp does for resolve.
#include "render/renderer_impl.hpp"
#include "scene/instance_transform.hpp"
#include "shared/visibility.h"

#include <clvis/flow.hpp>

#include <algorithm>
#include <cmath>

namespace clvis {

using namespace detail;

struct FlowAccess {
    static const Device& device(const FlowBuffer& f) { return f.device_; }
    static std::shared_ptr<_cl_mem>& buffer(FlowBuffer& f) { return f.buffer_; }
    static void set(FlowBuffer& f, const Device& device, int width, int height)
    {
        f.device_ = device;
        f.width_ = width;
        f.height_ = height;
    }
};

namespace {

std::size_t flow_bytes(int width, int height)
{
    return std::size_t(width) * std::size_t(height) * flow_channels * sizeof(float);
}

cl::Buffer upload(Renderer::Impl& r, const void* data, std::size_t bytes)
{
    cl::Buffer b(r.dev().context, CL_MEM_READ_ONLY, std::max<std::size_t>(bytes, 16));
    if (bytes) r.queue.enqueueWriteBuffer(b, CL_TRUE, 0, bytes, data);
    return b;
}

void check_items(const Scene& scene, const ItemTransforms& items, const char* which)
{
    for (const auto& [item, t] : items) {
        std::string where = std::string("flow: ") + which + "[" + std::to_string(item) + "]";
        if (item >= scene.meshes().size())
            throw Error(Error::Kind::InvalidArgument, where + ": no such item (the scene has " +
                                                          std::to_string(scene.meshes().size()) + ")");
        for (double v : t.m)
            if (!std::isfinite(v)) throw Error(Error::Kind::InvalidArgument, where + ": a non-finite entry");
        if (t(3, 0) != 0 || t(3, 1) != 0 || t(3, 2) != 0 || t(3, 3) != 1)
            throw Error(Error::Kind::InvalidArgument, where + ": the last row must be 0 0 0 1");
    }
}

/// The triangles A's keys show, their corners at A and at B (9 floats each, float32 world space
/// as the expansion would hold them), and A's keys renumbered into them.
struct PlacedTriangles {
    std::vector<float> at_a, at_b;
    std::vector<std::uint64_t> keys;
    std::uint32_t count = 0;
};

PlacedTriangles place_visible(const Scene& scene, const VisibilityBuffer& a, const ItemTransforms& items_a,
                              const ItemTransforms& items_b)
{
    PlacedTriangles out;
    out.keys = a.read_keys();
    std::vector<std::uint32_t> ids;
    std::uint32_t last = CLVIS_BACKGROUND_ID; // neighbouring samples mostly share a triangle
    for (std::uint64_t key : out.keys)
        if (std::uint32_t(key) < scene.triangle_count() && std::uint32_t(key) != last)
            ids.push_back(last = std::uint32_t(key));
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    out.count = std::uint32_t(ids.size());
    out.at_a.resize(ids.size() * 9);
    out.at_b.resize(ids.size() * 9);
    auto transform_at = [&](const ItemTransforms& items, std::size_t item) -> const Mat4& {
        auto it = items.find(item);
        return it != items.end() ? it->second : scene.meshes()[item].transform;
    };
    for (std::size_t i = 0; i < ids.size(); ++i) {
        std::size_t item = scene.mesh_of(ids[i]);
        const MeshData& data = scene.data_of(item);
        std::size_t local = ids[i] - scene.meshes()[item].first_triangle;
        const Mat4& ta = transform_at(items_a, item);
        const Mat4& tb = transform_at(items_b, item);
        for (std::size_t k = 0; k < 3; ++k) {
            const float* p = &data.positions[std::size_t(data.indices[local * 3 + k]) * 3];
            transform_positions(ta, p, 1, &out.at_a[i * 9 + k * 3]);
            transform_positions(tb, p, 1, &out.at_b[i * 9 + k * 3]);
        }
        for (std::size_t c = 0; c < 9; ++c)
            if (!std::isfinite(out.at_a[i * 9 + c]) || !std::isfinite(out.at_b[i * 9 + c]))
                throw Error(Error::Kind::InvalidArgument,
                            "mesh '" + data.name + "': a transformed vertex overflows float32");
    }
    std::uint32_t from = CLVIS_BACKGROUND_ID, to = CLVIS_BACKGROUND_ID;
    for (std::uint64_t& key : out.keys) {
        std::uint32_t id = std::uint32_t(key);
        if (id != from) {
            from = id;
            to = id < scene.triangle_count()
                     ? std::uint32_t(std::lower_bound(ids.begin(), ids.end(), id) - ids.begin())
                     : CLVIS_BACKGROUND_ID;
        }
        key = (key & ~std::uint64_t(0xFFFFFFFFu)) | to;
    }
    return out;
}

} // namespace

cl_mem FlowBuffer::buffer() const
{
    if (!buffer_) throw Error(Error::Kind::InvalidArgument, "use of an empty FlowBuffer");
    return buffer_.get();
}

void FlowBuffer::read(float* out) const
{
    cl_mem mem = buffer();
    auto& impl = DeviceAccess::of(device_, "FlowBuffer::read");
    try {
        std::lock_guard<std::mutex> lock(impl.mutex);
        impl.queue.enqueueReadBuffer(cl::Buffer(mem, true), CL_TRUE, 0, flow_bytes(width_, height_), out);
    } catch (const cl::Error& e) {
        throw_cl_error(e, "reading a flow buffer back");
    }
}

void FlowBuffer::read(std::vector<float>& out) const
{
    out.resize(flow_bytes(width_, height_) / sizeof(float));
    read(out.data());
}

std::vector<float> FlowBuffer::read() const
{
    std::vector<float> out;
    read(out);
    return out;
}

void flow(Renderer& renderer, const VisibilityBuffer& a, const Camera& camera_a, const VisibilityBuffer& b,
          const Camera& camera_b, FlowBuffer& target, const ItemTransforms& items_a, const ItemTransforms& items_b)
{
    camera_a.validate();
    camera_b.validate();
    if (a.empty() || b.empty()) throw Error(Error::Kind::InvalidArgument, "flow: empty visibility buffer");
    if (a.width() != b.width() || a.height() != b.height())
        throw Error(Error::Kind::InvalidArgument, "flow: views of one size are expected, got " +
                                                      std::to_string(a.width()) + "x" + std::to_string(a.height()) +
                                                      " and " + std::to_string(b.width()) + "x" +
                                                      std::to_string(b.height()));
    if (a.samples() != 1 || b.samples() != 1)
        throw Error(Error::Kind::InvalidArgument, "flow: one sample per pixel is expected, the buffers hold " +
                                                      std::to_string(a.samples()) + " and " +
                                                      std::to_string(b.samples()) + " (render with samples = 1)");
    Renderer::Impl& r = RendererAccess::of(renderer, "flow");
    if (a.device().context() != r.device.context() || b.device().context() != r.device.context())
        throw Error(Error::Kind::InvalidArgument, "flow: a buffer belongs to another OpenCL context");
    check_items(r.scene, items_a, "items_a");
    check_items(r.scene, items_b, "items_b");
    bool same_size = target.width() == a.width() && target.height() == a.height() && FlowAccess::device(target) &&
                     FlowAccess::device(target).context() == r.device.context();
    FlowAccess::set(target, r.device, a.width(), a.height());
    try {
        auto& held = FlowAccess::buffer(target);
        if (!held || !same_size) {
            std::size_t bytes = flow_bytes(a.width(), a.height());
            r.dev().check_allocation(bytes, "a flow buffer");
            cl::Buffer made(r.dev().context, CL_MEM_READ_WRITE, bytes);
            clRetainMemObject(made());
            held = std::shared_ptr<_cl_mem>(made(), clReleaseMemObject);
        }
        cl::Kernel kernel(r.dev().program("flow"), "flow");
        clvis_camera_gpu ga = make_gpu_camera(camera_a, a.width(), a.height());
        clvis_camera_gpu gb = make_gpu_camera(camera_b, b.width(), b.height());
        cl::Buffer keys_a, positions_a, positions_b, indices;
        std::uint32_t triangles = 0;
        if (!r.instanced && items_a.empty() && items_b.empty()) { // the resident expansion at both views
            DeviceScene& s = r.scene_buffers();
            keys_a = cl::Buffer(a.keys(), true);
            positions_a = positions_b = s.positions;
            indices = s.indices;
            triangles = s.triangle_count;
        } else {
            PlacedTriangles placed = place_visible(r.scene, a, items_a, items_b);
            std::vector<std::uint32_t> identity(std::size_t(placed.count) * 3);
            for (std::size_t i = 0; i < identity.size(); ++i) identity[i] = std::uint32_t(i);
            keys_a = upload(r, placed.keys.data(), placed.keys.size() * 8);
            positions_a = upload(r, placed.at_a.data(), placed.at_a.size() * 4);
            positions_b = upload(r, placed.at_b.data(), placed.at_b.size() * 4);
            indices = upload(r, identity.data(), identity.size() * 4);
            triangles = placed.count;
        }
        kernel.setArg(0, keys_a);
        kernel.setArg(1, sizeof ga, &ga);
        kernel.setArg(2, cl::Buffer(b.keys(), true));
        kernel.setArg(3, sizeof gb, &gb);
        kernel.setArg(4, positions_a);
        kernel.setArg(5, positions_b);
        kernel.setArg(6, indices);
        kernel.setArg(7, cl_uint(triangles));
        kernel.setArg(8, cl::Buffer(held.get(), true));
        r.queue.enqueueNDRangeKernel(kernel, cl::NullRange,
                                     cl::NDRange(round_up(a.width(), 8), round_up(a.height(), 8)), cl::NDRange(8, 8));
        r.queue.finish();
    } catch (const cl::Error& e) {
        throw_cl_error(e, "computing the flow between two views");
    }
}

FlowBuffer flow(Renderer& renderer, const VisibilityBuffer& a, const Camera& camera_a, const VisibilityBuffer& b,
                const Camera& camera_b, const ItemTransforms& items_a, const ItemTransforms& items_b)
{
    FlowBuffer out;
    flow(renderer, a, camera_a, b, camera_b, out, items_a, items_b);
    return out;
}

} // namespace clvis
