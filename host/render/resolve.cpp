// Resolving a visibility buffer into attributes (kernels/resolve.cl) on the renderer's queue, and
// reading them back into the caller's storage.
#include "render/attribute_access.hpp"

#include "shared/resolve.h"

#include <clvis/attributes.hpp>

namespace clvis {

using namespace detail;

namespace {

constexpr Attribute all_attributes[attribute_count] = {Attribute::Barycentrics, Attribute::Position,
                                                       Attribute::Normal, Attribute::SmoothNormal};
constexpr int resolve_bits[attribute_count] = {CLVIS_RESOLVE_BARY, CLVIS_RESOLVE_POSITION, CLVIS_RESOLVE_NORMAL,
                                               CLVIS_RESOLVE_SMOOTH_NORMAL};

std::size_t attribute_bytes(const AttributeBuffers& a, Attribute which)
{
    return std::size_t(a.width()) * std::size_t(a.height()) * std::size_t(channels(which)) * sizeof(float);
}

} // namespace

int channels(Attribute a) noexcept { return a == Attribute::Barycentrics ? 2 : 3; }

bool AttributeRequest::has(Attribute a) const noexcept
{
    switch (a) {
    case Attribute::Barycentrics: return barycentrics;
    case Attribute::Position: return position;
    case Attribute::Normal: return normal;
    case Attribute::SmoothNormal: return smooth_normal;
    }
    return false;
}

cl_mem AttributeBuffers::buffer(Attribute a) const
{
    if (!has(a))
        throw Error(Error::Kind::InvalidArgument, std::string("the ") + to_string(a) + " attribute was not resolved");
    return buffers_[std::size_t(a)].get();
}

void AttributeBuffers::read(Attribute a, float* out) const
{
    cl_mem mem = buffer(a);
    auto& impl = DeviceAccess::of(device_, "AttributeBuffers::read");
    try {
        std::lock_guard<std::mutex> lock(impl.mutex);
        impl.queue.enqueueReadBuffer(cl::Buffer(mem, true), CL_TRUE, 0, attribute_bytes(*this, a), out);
    } catch (const cl::Error& e) {
        throw_cl_error(e, std::string("reading the ") + to_string(a) + " attribute back");
    }
}

void AttributeBuffers::read(Attribute a, std::vector<float>& out) const
{
    out.resize(attribute_bytes(*this, a) / sizeof(float));
    read(a, out.data());
}

std::vector<float> AttributeBuffers::read(Attribute a) const
{
    std::vector<float> out;
    read(a, out);
    return out;
}

void resolve(Renderer& renderer, const VisibilityBuffer& vis, const Camera& camera, const AttributeRequest& request,
             AttributeBuffers& target)
{
    camera.validate();
    if (vis.empty()) throw Error(Error::Kind::InvalidArgument, "resolve: empty visibility buffer");
    if (vis.samples() != 1)
        throw Error(Error::Kind::InvalidArgument,
                    "resolve: attributes are resolved at one sample per pixel, the buffer holds " +
                        std::to_string(vis.samples()) +
                        " (render with samples = 1 for barycentrics, normals, positions, named attributes and objects)");
    Renderer::Impl& r = RendererAccess::of(renderer, "resolve");
    if (vis.device().context() != r.device.context())
        throw Error(Error::Kind::InvalidArgument, "resolve: the buffer belongs to another OpenCL context");
    // Buffers of the same size on the same context are kept.
    bool same_size = target.width() == vis.width() && target.height() == vis.height() &&
                     AttributeAccess::device(target) && AttributeAccess::device(target).context() == r.device.context();
    AttributeAccess::set(target, r.device, vis.width(), vis.height());
    try {
        cl::Buffer dummy(r.dev().context, CL_MEM_READ_WRITE, 16);
        cl::Kernel kernel(r.dev().program("resolve"), "resolve");
        clvis_camera_gpu g = make_gpu_camera(camera, vis.width(), vis.height());
        const bool builtin = request.barycentrics || request.position || request.normal || request.smooth_normal;
        SampleScene scene; // a scene with instances: the keys' triangles
        if (builtin || !request.named.empty()) scene = sample_scene(r, vis, true);
        kernel.setArg(1, sizeof g, &g);
        if (builtin) {
            kernel.setArg(0, scene.keys);
            scene.scene.set_args(kernel, 2);
        }
        int what = 0;
        for (int k = 0; k < attribute_count; ++k) {
            Attribute a = all_attributes[k];
            auto& held = AttributeAccess::buffer(target, a);
            if (!request.has(a)) {
                held.reset();
                kernel.setArg(8 + k, dummy);
                continue;
            }
            if (!held || !same_size) {
                std::size_t bytes = attribute_bytes(target, a);
                r.dev().check_allocation(bytes, std::string("the ") + to_string(a) + " attribute");
                cl::Buffer made(r.dev().context, CL_MEM_READ_WRITE, bytes);
                clRetainMemObject(made());
                held = std::shared_ptr<_cl_mem>(made(), clReleaseMemObject);
            }
            kernel.setArg(8 + k, cl::Buffer(held.get(), true));
            what |= resolve_bits[k];
        }
        if (what != 0) {
            if (request.normal_space == NormalSpace::Camera) what |= CLVIS_RESOLVE_CAMERA_SPACE;
            kernel.setArg(7, cl_int(what));
            r.queue.enqueueNDRangeKernel(kernel, cl::NullRange,
                                         cl::NDRange(round_up(vis.width(), 8), round_up(vis.height(), 8)),
                                         cl::NDRange(8, 8));
            r.queue.finish();
        }
        resolve_corners(r, vis, camera, request, target, same_size,
                        builtin || !request.named.empty() ? &scene : nullptr);
    } catch (const cl::Error& e) {
        throw_cl_error(e, "resolving attributes of a visibility buffer");
    }
}

AttributeBuffers resolve(Renderer& renderer, const VisibilityBuffer& vis, const Camera& camera,
                         const AttributeRequest& request)
{
    AttributeBuffers out;
    resolve(renderer, vis, camera, request, out);
    return out;
}

} // namespace clvis
