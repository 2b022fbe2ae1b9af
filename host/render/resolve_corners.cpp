// Object ids and named corner attributes resolved on the device (kernels/resolve_corners.cl):
// the items' first ids and each attribute's corner values uploaded once per renderer, the first
// time they are asked for (each mesh and prototype once: an instance reads its prototype's).
#include "render/attribute_access.hpp"

#include <algorithm>
#include <cmath>

namespace clvis {

using namespace detail;

const char* to_string(NormalSpace s) noexcept { return s == NormalSpace::Camera ? "camera" : "world"; }

NormalSpace normal_space_from_string(const std::string& name)
{
    if (name == "world") return NormalSpace::World;
    if (name == "camera") return NormalSpace::Camera;
    throw Error(Error::Kind::InvalidArgument, "normal space '" + name + "': expected world or camera");
}

std::vector<AttributeInfo> scene_attributes(const Scene& scene)
{
    std::vector<AttributeInfo> out;
    std::vector<std::string> first_mesh;
    for (std::size_t item = 0; item < scene.meshes().size(); ++item) {
        const MeshData& data = scene.data_of(item);
        for (const CornerAttribute& a : data.attributes) {
            std::size_t k = 0;
            while (k < out.size() && out[k].name != a.name) ++k;
            if (k == out.size()) {
                out.push_back({a.name, a.components});
                first_mesh.push_back(data.name);
            } else if (out[k].components != a.components) {
                throw Error(Error::Kind::InvalidArgument,
                            "attribute '" + a.name + "' has " + std::to_string(out[k].components) +
                                " components in mesh '" + first_mesh[k] + "' and " + std::to_string(a.components) +
                                " in mesh '" + data.name + "'");
            }
        }
    }
    return out;
}

const AttributeAccess::Named& AttributeBuffers::named(const std::string& name) const
{
    for (const Named& n : named_)
        if (n.name == name) return n;
    throw Error(Error::Kind::InvalidArgument, "the attribute '" + name + "' was not resolved");
}

bool AttributeBuffers::has(const std::string& name) const
{
    for (const Named& n : named_)
        if (n.name == name) return true;
    return false;
}

int AttributeBuffers::components(const std::string& name) const { return named(name).components; }
cl_mem AttributeBuffers::buffer(const std::string& name) const { return named(name).buffer.get(); }

std::vector<std::string> AttributeBuffers::names() const
{
    std::vector<std::string> out;
    for (const Named& n : named_) out.push_back(n.name);
    return out;
}

namespace {

/// A blocking read of `bytes` from `mem` into `out` on the device's queue.
void read_buffer(const Device& device, cl_mem mem, std::size_t bytes, void* out, const std::string& what)
{
    auto& impl = DeviceAccess::of(device, "AttributeBuffers::read");
    try {
        std::lock_guard<std::mutex> lock(impl.mutex);
        impl.queue.enqueueReadBuffer(cl::Buffer(mem, true), CL_TRUE, 0, bytes, out);
    } catch (const cl::Error& e) {
        throw_cl_error(e, "reading " + what + " back");
    }
}

} // namespace

void AttributeBuffers::read(const std::string& name, std::vector<float>& out) const
{
    const Named& n = named(name);
    out.resize(std::size_t(width_) * std::size_t(height_) * std::size_t(n.components));
    read_buffer(device_, n.buffer.get(), out.size() * sizeof(float), out.data(), "the " + name + " attribute");
}

cl_mem AttributeBuffers::objects_buffer() const
{
    if (!objects_) throw Error(Error::Kind::InvalidArgument, "the object ids were not resolved");
    return objects_.get();
}

void AttributeBuffers::read_objects(std::vector<std::uint32_t>& out) const
{
    cl_mem mem = objects_buffer();
    out.resize(std::size_t(width_) * std::size_t(height_));
    read_buffer(device_, mem, out.size() * sizeof(std::uint32_t), out.data(), "the object ids");
}

namespace detail {

namespace {

cl::Buffer upload(Renderer::Impl& r, const void* data, std::size_t bytes, const std::string& what)
{
    r.dev().check_allocation(bytes, what);
    cl::Buffer b(r.dev().context, CL_MEM_READ_ONLY, std::max<std::size_t>(bytes, 16));
    if (bytes) r.queue.enqueueWriteBuffer(b, CL_TRUE, 0, bytes, data);
    return b;
}

/// `held` as a buffer of `bytes` (made anew unless `keep`).
cl::Buffer output(Renderer::Impl& r, std::shared_ptr<_cl_mem>& held, bool keep, std::size_t bytes,
                  const std::string& what)
{
    if (!held || !keep) {
        r.dev().check_allocation(bytes, what);
        cl::Buffer made(r.dev().context, CL_MEM_READ_WRITE, bytes);
        clRetainMemObject(made());
        held = std::shared_ptr<_cl_mem>(made(), clReleaseMemObject);
    }
    return cl::Buffer(held.get(), true);
}

/// The corner values of `name` on the device: every plain mesh's and prototype's once, and where
/// each item's start (an instance: its prototype's).
CornerCache::Values upload_values(Renderer::Impl& r, const std::string& name, int components)
{
    const Scene& scene = r.scene;
    std::vector<float> values;
    constexpr std::uint64_t none = ~std::uint64_t(0);
    std::vector<std::uint64_t> proto_base(scene.prototypes().size(), none), base(scene.meshes().size(), none);
    auto append = [&](const MeshData& data) {
        for (const CornerAttribute& a : data.attributes)
            if (a.name == name) {
                std::uint64_t at = values.size();
                values.insert(values.end(), a.values.begin(), a.values.end());
                return at;
            }
        return none;
    };
    for (std::size_t p = 0; p < scene.prototypes().size(); ++p) proto_base[p] = append(scene.prototypes()[p]);
    for (std::size_t item = 0; item < scene.meshes().size(); ++item) {
        const Scene::Mesh& m = scene.meshes()[item];
        base[item] = m.prototype == Scene::no_prototype ? append(m.data) : proto_base[m.prototype];
    }
    CornerCache::Values v;
    v.components = components;
    v.values = upload(r, values.data(), values.size() * sizeof(float), "the corner values of '" + name + "'");
    v.base = upload(r, base.data(), base.size() * sizeof(std::uint64_t), "the items of '" + name + "'");
    return v;
}

std::string listed(const std::vector<AttributeInfo>& infos)
{
    if (infos.empty()) return "it has none";
    std::string s = "it has ";
    for (std::size_t k = 0; k < infos.size(); ++k) s += (k ? ", " : "") + infos[k].name;
    return s;
}

/// The camera of CONVENTIONS.md in double, each number as a float pair (hi, lo) whose sum is it
/// to 48 bits: eye, r, u, f, fx, fy, cx, cy (kernels/resolve_corners.cl).
std::vector<float> camera_pairs(const Camera& camera, int width, int height)
{
    CameraFrame fr = camera.frame();
    Intrinsics k = camera.raster_map(width, height);
    const double v[16] = {camera.eye.x, camera.eye.y, camera.eye.z, fr.r.x, fr.r.y, fr.r.z, fr.u.x, fr.u.y,
                          fr.u.z,       fr.f.x,       fr.f.y,       fr.f.z, k.fx,   k.fy,   k.cx,   k.cy};
    std::vector<float> out(32);
    for (int i = 0; i < 16; ++i) {
        out[2 * i] = float(v[i]);
        out[2 * i + 1] = float(v[i] - double(out[2 * i]));
    }
    return out;
}

} // namespace

void resolve_corners(Renderer::Impl& r, const VisibilityBuffer& vis, const Camera& camera,
                     const AttributeRequest& request, AttributeBuffers& target, bool same_size,
                     const SampleScene* scene)
{
    auto& named = AttributeAccess::named(target);
    auto& objects_held = AttributeAccess::objects(target);
    // The names asked, checked before anything runs (once each, in the order asked).
    std::vector<AttributeInfo> asked;
    if (!request.named.empty()) {
        const std::vector<AttributeInfo> infos = scene_attributes(r.scene);
        for (const std::string& name : request.named) {
            bool seen = false;
            for (const AttributeInfo& a : asked) seen |= a.name == name;
            if (seen) continue;
            std::size_t k = 0;
            while (k < infos.size() && infos[k].name != name) ++k;
            if (k == infos.size())
                throw Error(Error::Kind::InvalidArgument,
                            "resolve: attribute '" + name + "': the scene has no such vertex attribute (" +
                                listed(infos) + ")");
            asked.push_back(infos[k]);
        }
    }
    // Buffers kept for the names asked again at the same size; the others released.
    std::vector<AttributeAccess::Named> kept;
    for (const AttributeInfo& a : asked) {
        AttributeAccess::Named n{a.name, a.components, nullptr};
        for (auto& old : named)
            if (old.name == a.name && old.components == a.components && same_size) n.buffer = old.buffer;
        kept.push_back(n);
    }
    named = std::move(kept);
    if (!request.object) objects_held.reset();
    if (!request.object && asked.empty()) return;

    const std::size_t pixels = std::size_t(vis.width()) * std::size_t(vis.height());
    if (!r.corners) r.corners = std::make_shared<CornerCache>();
    CornerCache& cache = *r.corners;
    if (!cache.has_first) {
        std::vector<std::uint32_t> first;
        for (const Scene::Mesh& m : r.scene.meshes()) first.push_back(m.first_triangle);
        cache.first = upload(r, first.data(), first.size() * sizeof(std::uint32_t), "the items' first ids");
        cache.has_first = true;
    }
    std::shared_ptr<_cl_mem> scratch; // the objects of a request for attributes only
    cl::Buffer objects = output(r, request.object ? objects_held : scratch, same_size,
                                pixels * sizeof(std::uint32_t), "the object ids");
    const cl::NDRange global(round_up(vis.width(), 8), round_up(vis.height(), 8)), local(8, 8);
    cl::Buffer keys(vis.keys(), true);
    cl::Kernel items(r.dev().program("resolve_corners"), "resolve_objects");
    items.setArg(0, keys);
    items.setArg(1, cl_int(vis.width()));
    items.setArg(2, cl_int(vis.height()));
    items.setArg(3, cl_uint(r.scene.triangle_count()));
    items.setArg(4, cache.first);
    items.setArg(5, cl_uint(r.scene.meshes().size()));
    items.setArg(6, objects);
    r.queue.enqueueNDRangeKernel(items, cl::NullRange, global, local);
    if (!asked.empty()) {
        // The exact barycentrics once, then each attribute interpolated with them.
        std::vector<float> pairs = camera_pairs(camera, vis.width(), vis.height());
        cl::Buffer cam = upload(r, pairs.data(), pairs.size() * sizeof(float), "the camera");
        r.dev().check_allocation(pixels * 2 * sizeof(float), "the exact barycentrics");
        cl::Buffer bary(r.dev().context, CL_MEM_READ_WRITE, pixels * 2 * sizeof(float));
        cl::Kernel exact(r.dev().program("resolve_corners"), "resolve_exact_barycentrics");
        int a = 0;
        exact.setArg(a++, scene->keys);
        exact.setArg(a++, cam);
        exact.setArg(a++, cl_int(camera.projection == Projection::Orthographic));
        exact.setArg(a++, cl_int(vis.width()));
        exact.setArg(a++, cl_int(vis.height()));
        exact.setArg(a++, scene->scene.positions);
        exact.setArg(a++, scene->scene.indices);
        exact.setArg(a++, cl_uint(scene->scene.triangle_count));
        exact.setArg(a++, bary);
        r.queue.enqueueNDRangeKernel(exact, cl::NullRange, global, local);
        for (AttributeAccess::Named& n : named) {
            auto it = cache.named.find(n.name);
            if (it == cache.named.end()) it = cache.named.emplace(n.name, upload_values(r, n.name, n.components)).first;
            cl::Buffer out = output(r, n.buffer, bool(n.buffer), pixels * std::size_t(n.components) * sizeof(float),
                                    "the " + n.name + " attribute");
            cl::Kernel k(r.dev().program("resolve_corners"), "resolve_corners");
            a = 0;
            k.setArg(a++, keys);
            k.setArg(a++, objects);
            k.setArg(a++, bary);
            k.setArg(a++, cl_int(vis.width()));
            k.setArg(a++, cl_int(vis.height()));
            k.setArg(a++, cache.first);
            k.setArg(a++, it->second.base);
            k.setArg(a++, cl_int(n.components));
            k.setArg(a++, it->second.values);
            k.setArg(a++, out);
            r.queue.enqueueNDRangeKernel(k, cl::NullRange, global, local);
        }
    }
    r.queue.finish();
}

} // namespace detail
} // namespace clvis
