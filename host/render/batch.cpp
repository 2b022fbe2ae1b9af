// Many views per call (include/clvis/batch.hpp): one buffer of keys cut into per-view
// sub-buffers, the cameras uploaded once per batch, the ray path's single launch and the raster
// and brute paths' view-by-view enqueues with one wait at the end.
#include "render/renderer_impl.hpp"

#include <clvis/batch.hpp>

#include <algorithm>
#include <chrono>

namespace clvis {

using namespace detail;

VisibilityBatch::VisibilityBatch(const Device& device, int views, int width, int height)
    : VisibilityBatch(device, views, width, height, 1)
{
}

VisibilityBatch::VisibilityBatch(const Device& device, int views, int width, int height, int layers)
    : device_(device), width_(width), height_(height), layers_(layers)
{
    check_layers(layers);
    if (views <= 0 || width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument, "VisibilityBatch: views and size must be positive, got " +
                                                      std::to_string(views) + " views of " + std::to_string(width) +
                                                      "x" + std::to_string(height));
    auto& impl = DeviceAccess::of(device, "VisibilityBatch");
    // Sub-buffers must start on the device's base address alignment (in bits).
    std::size_t align_keys = std::max<std::size_t>(impl.device.getInfo<CL_DEVICE_MEM_BASE_ADDR_ALIGN>() / 64, 1);
    stride_ = round_up(std::size_t(width) * std::size_t(height) * std::size_t(layers), align_keys);
    std::uint64_t bytes = std::uint64_t(stride_) * std::uint64_t(views) * 8;
    impl.check_allocation(bytes, "a batch of " + std::to_string(views) + " visibility buffers");
    try {
        cl::Buffer all(impl.context, CL_MEM_READ_WRITE, bytes);
        for (int v = 0; v < views; ++v) {
            cl_buffer_region region{std::size_t(v) * stride_ * 8,
                                    std::size_t(width) * std::size_t(height) * std::size_t(layers) * 8};
            cl::Buffer view = all.createSubBuffer(CL_MEM_READ_WRITE, CL_BUFFER_CREATE_TYPE_REGION, &region);
            buffers_.push_back(VisibilityBuffer::wrap(device, view(), width, height, 1, layers));
        }
        clRetainMemObject(all());
        keys_ = std::shared_ptr<_cl_mem>(all(), clReleaseMemObject);
    } catch (const cl::Error& e) {
        throw_cl_error(e, "allocating a batch of " + std::to_string(views) + " visibility buffers");
    }
}

cl_mem VisibilityBatch::keys() const
{
    if (!keys_) throw Error(Error::Kind::InvalidArgument, "use of an empty VisibilityBatch");
    return keys_.get();
}

const VisibilityBuffer& VisibilityBatch::view(int v) const
{
    if (v < 0 || v >= views())
        throw Error(Error::Kind::InvalidArgument, "VisibilityBatch::view: no view " + std::to_string(v) + " of " +
                                                      std::to_string(views()));
    return buffers_[std::size_t(v)];
}

void render_views(Renderer& renderer, const std::vector<Camera>& cameras, Path path, VisibilityBatch& target)
{
    for (const Camera& c : cameras) c.validate();
    if (target.views() == 0) throw Error(Error::Kind::InvalidArgument, "render_views: empty target batch");
    if (int(cameras.size()) != target.views())
        throw Error(Error::Kind::InvalidArgument, "render_views: " + std::to_string(cameras.size()) +
                                                      " cameras for a batch of " + std::to_string(target.views()));
    Renderer::Impl& m = RendererAccess::of(renderer, "render_views");
    if (m.options.samples != 1)
        throw Error(Error::Kind::InvalidArgument,
                    "render_views: a batch holds one sample per pixel, the Renderer's options ask for " +
                        std::to_string(m.options.samples) + " (render those views one by one)");
    if (m.options.layers != target.layers())
        throw Error(Error::Kind::InvalidArgument,
                    "render_views: the batch holds " + std::to_string(target.layers()) +
                        " depth layer(s) per view, the Renderer's options ask for layers " +
                        std::to_string(m.options.layers) + " (VisibilityBatch(device, views, width, height, layers))");
    if (target.view(0).device().context() != m.device.context())
        throw Error(Error::Kind::InvalidArgument, "render_views: the batch belongs to another OpenCL context");
    renderer.prepare(path);
    std::vector<clvis_camera_gpu> gpu;
    for (const Camera& c : cameras) gpu.push_back(make_gpu_camera(c, target.width(), target.height()));
    try {
        auto t0 = std::chrono::steady_clock::now();
        if (path == Path::Ray) {
            ViewsFrame f;
            f.queue = m.queue;
            f.cameras = cl::Buffer(m.dev().context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                   gpu.size() * sizeof(clvis_camera_gpu), gpu.data());
            f.views = target.views();
            f.width = target.width();
            f.height = target.height();
            f.keys = cl::Buffer(target.keys(), true);
            f.stride = target.stride();
            f.stages = &m.stages;
            m.ray->render_views(f);
        } else {
            for (int v = 0; v < target.views(); ++v) {
                Frame frame;
                frame.layers = m.options.layers;
                frame.queue = m.queue;
                frame.width = target.width();
                frame.height = target.height();
                frame.region = clvis_region{0, 0, target.width(), target.height()};
                frame.gpu_camera = gpu[std::size_t(v)];
                frame.keys = cl::Buffer(target.view(v).keys(), true);
                frame.stages = &m.stages;
                if (path == Path::Raster && m.instanced) m.raster->render(m.item_buffers(), frame, m.raster_chunk);
                else if (path == Path::Raster) m.raster->render(m.scene_buffers(), frame);
                else m.ray->render(m.scene_buffers(), frame, true);
            }
        }
        m.queue.finish();
        m.last.frame_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        std::optional<std::vector<StageTiming>> measured = m.stages.collect_sum();
        m.last.stages_measured = measured.has_value();
        m.last.stages = measured ? std::move(*measured) : std::vector<StageTiming>{};
    } catch (const cl::Error& e) {
        m.stages.collect();
        throw_cl_error(e, std::string("rendering a batch of views with the ") + to_string(path) + " path");
    }
}

} // namespace clvis
