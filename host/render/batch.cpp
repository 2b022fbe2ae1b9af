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

namespace {

/// Views [first, first + count) of `target` drawn with `gpu`'s cameras, enqueued on the Renderer's
/// queue without a wait.
void enqueue_views(Renderer::Impl& m, const std::vector<clvis_camera_gpu>& gpu, int first, int count, Path path,
                   VisibilityBatch& target)
{
    if (path == Path::Ray) {
        ViewsFrame f;
        f.queue = m.queue;
        f.cameras = cl::Buffer(m.dev().context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                               std::size_t(count) * sizeof(clvis_camera_gpu),
                               const_cast<clvis_camera_gpu*>(gpu.data()) + first);
        f.views = count;
        f.width = target.width();
        f.height = target.height();
        if (first == 0 && count == target.views()) {
            f.keys = cl::Buffer(target.keys(), true);
        } else { // a run of views: the keys from view `first` on (sub-buffers start on the alignment)
            cl::Buffer all(target.keys(), true);
            cl_buffer_region region{std::size_t(first) * target.stride() * 8,
                                    std::size_t(count) * target.stride() * 8};
            f.keys = all.createSubBuffer(CL_MEM_READ_WRITE, CL_BUFFER_CREATE_TYPE_REGION, &region);
        }
        f.stride = target.stride();
        f.stages = &m.stages;
        m.ray->render_views(f);
        return;
    }
    for (int v = first; v < first + count; ++v) {
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
        else m.render_brute(frame);
    }
}

/// render_views' checks; returns the Renderer's state and the cameras as the kernels take them.
Renderer::Impl& check_views(Renderer& renderer, const std::vector<Camera>& cameras, Path path,
                            const VisibilityBatch& target, std::vector<clvis_camera_gpu>& gpu)
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
    for (const Camera& c : cameras) gpu.push_back(make_gpu_camera(c, target.width(), target.height()));
    return m;
}

/// Waits for the batch and records its timing (frame_ms from `t0`) and the raster depth test.
void finish_views(Renderer::Impl& m, Path path, std::chrono::steady_clock::time_point t0)
{
    m.queue.finish();
    m.last.frame_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::optional<std::vector<StageTiming>> measured = m.stages.collect_sum();
    m.last.stages_measured = measured.has_value();
    m.last.stages = measured ? std::move(*measured) : std::vector<StageTiming>{};
    m.last.raster_atomics = m.raster_depth_test(path); // the views of a batch share the decision
}

bool same_transforms(const ItemTransforms& a, const ItemTransforms& b)
{
    if (a.size() != b.size()) return false;
    for (auto i = a.begin(), j = b.begin(); i != a.end(); ++i, ++j)
        if (i->first != j->first || i->second.m != j->second.m) return false;
    return true;
}

/// Puts the scene's own transforms back after a failure, keeping the first error.
template <class Place> void restore_quietly(Place& place, const ItemTransforms& base)
{
    try {
        place(base);
    } catch (...) {
    }
}

} // namespace

void render_views(Renderer& renderer, const std::vector<Camera>& cameras, Path path, VisibilityBatch& target)
{
    std::vector<clvis_camera_gpu> gpu;
    Renderer::Impl& m = check_views(renderer, cameras, path, target, gpu);
    try {
        auto t0 = std::chrono::steady_clock::now();
        enqueue_views(m, gpu, 0, target.views(), path, target);
        finish_views(m, path, t0);
    } catch (const cl::Error& e) {
        m.stages.collect();
        throw_cl_error(e, std::string("rendering a batch of views with the ") + to_string(path) + " path");
    }
}

void render_views(Renderer& renderer, Scene& scene, const std::vector<Camera>& cameras,
                  const std::vector<ItemTransforms>& items, Path path, VisibilityBatch& target)
{
    bool moves = false;
    for (const ItemTransforms& t : items) moves |= !t.empty();
    if (!moves) return render_views(renderer, cameras, path, target);
    if (items.size() != cameras.size())
        throw Error(Error::Kind::InvalidArgument, "render_views: " + std::to_string(items.size()) +
                                                      " sets of item transforms for " + std::to_string(cameras.size()) +
                                                      " cameras");
    // Every item some view moves, with the scene's own transform (restored at the end).
    ItemTransforms base;
    for (std::size_t v = 0; v < items.size(); ++v)
        for (const auto& [item, transform] : items[v]) {
            if (item >= scene.meshes().size())
                throw Error(Error::Kind::InvalidArgument, "render_views: view " + std::to_string(v) + " moves item " +
                                                              std::to_string(item) + ", the scene has " +
                                                              std::to_string(scene.meshes().size()));
            base.emplace(item, scene.meshes()[item].transform);
        }
    auto at_view = [&](std::size_t v) {
        ItemTransforms t = base;
        for (const auto& [item, transform] : items[v]) t[item] = transform;
        return t;
    };
    std::vector<clvis_camera_gpu> gpu;
    Renderer::Impl& m = check_views(renderer, cameras, path, target, gpu);
    auto place = [&](const ItemTransforms& t) {
        for (const auto& [item, transform] : t) scene.set_transform(item, transform);
        renderer.update(scene);
    };
    try {
        auto t0 = std::chrono::steady_clock::now();
        for (std::size_t first = 0; first < cameras.size();) {
            ItemTransforms here = at_view(first);
            std::size_t end = first + 1;
            while (end < cameras.size() && same_transforms(at_view(end), here)) ++end;
            place(here);
            enqueue_views(m, gpu, int(first), int(end - first), path, target);
            first = end;
        }
        finish_views(m, path, t0);
        place(base);
    } catch (const cl::Error& e) {
        m.stages.collect();
        restore_quietly(place, base);
        throw_cl_error(e, std::string("rendering a batch of moving views with the ") + to_string(path) + " path");
    } catch (...) {
        m.stages.collect();
        restore_quietly(place, base);
        throw;
    }
}

} // namespace clvis
