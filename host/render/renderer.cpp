// The Renderer: uploads the scene once, keeps it (and the BVH) resident, validates each frame's
// request, dispatches the chosen path and times it. The paths live in raster/raster_pipeline.hpp
// and ray/ray_pipeline.hpp, over the frame layer (frame/frame.hpp).
#include "render/renderer_impl.hpp"

#include "render/raster_tune.hpp"
#include "render/renderer_probe.hpp"
#include "render/sample_scene.hpp"
#include "render/ray_tune.hpp"

#include <clvis/renderer.hpp>

#include <chrono>
#include <optional>

namespace clvis {

using namespace detail;

namespace {

void check_options(const RenderOptions& o)
{
    if (o.tile_size != 0 && (o.tile_size < 4 || o.tile_size > 256 || (o.tile_size & (o.tile_size - 1))))
        throw Error(Error::Kind::InvalidArgument,
                    "tile size must be a power of two in [4, 256] (or 0 for the default), got " +
                        std::to_string(o.tile_size));
    if (o.bvh.max_leaf_size < 1 || o.bvh.max_leaf_size > 64)
        throw Error(Error::Kind::InvalidArgument,
                    "BVH leaf size must lie in [1, 64], got " + std::to_string(o.bvh.max_leaf_size));
    if (o.bvh.sah_bins < 2 || o.bvh.sah_bins > 256)
        throw Error(Error::Kind::InvalidArgument,
                    "BVH SAH bins must lie in [2, 256], got " + std::to_string(o.bvh.sah_bins));
    samples_log2(o.samples); // 1, 2, 4, 8 or 16
    check_layers(o.layers);  // 1 to 8
    if (o.layers > 1 && o.samples > 1)
        throw Error(Error::Kind::InvalidArgument, "layers " + std::to_string(o.layers) + " with samples " +
                                                      std::to_string(o.samples) +
                                                      ": depth layers take one sample per pixel");
    if (o.coverage != Coverage::Watertight && o.coverage != Coverage::RasterRule)
        throw Error(Error::Kind::InvalidArgument,
                    "unknown coverage mode " + std::to_string(static_cast<int>(o.coverage)));
}

/// A region of at least one pixel inside the width x height image.
void check_region(const Region& r, int width, int height)
{
    if (width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument, "image size must be positive, got " + std::to_string(width) + "x" +
                                                      std::to_string(height));
    if (r.width <= 0 || r.height <= 0 || r.x < 0 || r.y < 0 || r.x > width - r.width || r.y > height - r.height)
        throw Error(Error::Kind::InvalidArgument,
                    "region " + std::to_string(r.width) + "x" + std::to_string(r.height) + " at (" +
                        std::to_string(r.x) + ", " + std::to_string(r.y) + ") does not lie inside the " +
                        std::to_string(width) + "x" + std::to_string(height) + " image");
}

/// World-space vertex normals (world_normal of each vertex), zero where a mesh has none: shading
/// then falls back to the triangle's flat normal.
std::vector<float> world_normals(const Scene& scene)
{
    std::vector<float> out(scene.vertex_count() * 3, 0.0f);
    std::size_t v = 0;
    for (std::size_t item = 0; item < scene.meshes().size(); ++item) {
        const MeshData& data = scene.data_of(item);
        for (std::size_t i = 0; i < data.normals.size(); i += 3)
            world_normal(scene.meshes()[item].transform, &data.normals[i], &out[v * 3 + i]);
        v += data.vertex_count();
    }
    return out;
}

} // namespace

void Renderer::Impl::check_scene_fits()
{
    std::uint64_t pos_bytes = std::max<std::uint64_t>(scene.vertex_count() * 3 * 4, 16);
    std::uint64_t idx_bytes = std::max<std::uint64_t>(scene.triangle_count() * 3 * 4, 16);
    dev().check_allocation(pos_bytes, "the scene's " + std::to_string(scene.vertex_count()) + " vertices");
    dev().check_allocation(idx_bytes, "the scene's " + std::to_string(scene.triangle_count()) + " triangles");
    if (pos_bytes * 2 + idx_bytes > dev().info.global_memory)
        throw Error(Error::Kind::Limit, "the scene (" + std::to_string(scene.triangle_count()) +
                                            " triangles) does not fit in " + dev().info.name + "'s " +
                                            std::to_string(dev().info.global_memory) + " bytes");
}

void Renderer::Impl::upload_all()
{
    check_scene_fits();
    // The expansion made for this upload and freed after it (or the mesh's own arrays): the
    // Scene's cached world_positions() would keep a second host copy for the Renderer's life.
    WorldMesh world = world_mesh(scene);
    const std::size_t position_count = scene.vertex_count() * 3, index_count = scene.triangle_count() * 3;
    std::uint64_t pos_bytes = std::max<std::uint64_t>(position_count * 4, 16);
    std::uint64_t idx_bytes = std::max<std::uint64_t>(index_count * 4, 16);
    try {
        gpu.triangle_count = std::uint32_t(scene.triangle_count());
        gpu.vertex_count = std::uint32_t(scene.vertex_count());
        gpu.positions = cl::Buffer(dev().context, CL_MEM_READ_ONLY, pos_bytes);
        gpu.indices = cl::Buffer(dev().context, CL_MEM_READ_ONLY, idx_bytes);
        if (position_count) queue.enqueueWriteBuffer(gpu.positions, CL_FALSE, 0, position_count * 4, world.positions);
        if (index_count) queue.enqueueWriteBuffer(gpu.indices, CL_FALSE, 0, index_count * 4, world.indices);
        gpu.has_normals = false;
        for (std::size_t item = 0; item < scene.meshes().size(); ++item)
            gpu.has_normals |= !scene.data_of(item).normals.empty();
        if (gpu.has_normals) {
            auto normals = world_normals(scene);
            gpu.normals = cl::Buffer(dev().context, CL_MEM_READ_ONLY, pos_bytes);
            // Blocking: `normals` dies at the end of this block, before the finish below.
            queue.enqueueWriteBuffer(gpu.normals, CL_TRUE, 0, normals.size() * 4, normals.data());
        } else {
            gpu.normals = cl::Buffer(dev().context, CL_MEM_READ_ONLY, 16);
        }
        queue.finish();
    } catch (const cl::Error& e) {
        throw_cl_error(e, "uploading the scene to " + dev().info.name);
    }
}

void Renderer::Impl::upload_positions(std::size_t item, std::size_t first_vertex)
{
    // Only this item's vertices through its transform: world_positions()'s bits, nothing cached.
    std::vector<float> positions(scene.data_of(item).positions.size());
    item_world_positions(scene, item, positions.data());
    try {
        queue.enqueueWriteBuffer(gpu.positions, CL_TRUE, first_vertex * 12, positions.size() * 4, positions.data());
    } catch (const cl::Error& e) {
        throw_cl_error(e, "uploading changed vertices");
    }
}

const RasterMappingChoice& Renderer::Impl::raster_mapping()
{
    if (!raster_choice) raster_choice = choose_raster_mapping(device, options);
    return *raster_choice;
}

RasterPipeline& Renderer::Impl::raster_pipeline()
{
    if (!raster) {
        RenderOptions resolved = options;
        resolved.raster_mapping = raster_mapping().mapping;
        raster = std::make_unique<RasterPipeline>(dev(), resolved);
    }
    return *raster;
}

const RayMappingChoice& Renderer::Impl::ray_mapping()
{
    if (!ray_choice) ray_choice = choose_ray_mapping(device, options);
    return *ray_choice;
}

RayPipeline& Renderer::Impl::ray_pipeline()
{
    if (!ray) ray = std::make_unique<RayPipeline>(dev(), options);
    return *ray;
}

RayPipeline& Renderer::Impl::ray_pipeline_with_bvh()
{
    RayPipeline& p = ray_pipeline();
    if (!p.built()) p.build(scene, queue);
    return p;
}

RayPipeline& Renderer::Impl::primary_ray_pipeline()
{
    ray_pipeline().set_mapping(ray_mapping().mapping); // before the build makes its kernel
    return ray_pipeline_with_bvh();
}

void Renderer::Impl::prepare(Path path)
{
    if (path == Path::Raster) raster_pipeline();
    else if (path == Path::Ray) primary_ray_pipeline();
    else ray_pipeline();
}

namespace {

/// Both constructors: `take` gives the Renderer its scene (a copy, or the caller's moved in).
template <class Take>
void make_renderer(Renderer::Impl& m, Device& device, const RenderOptions& options, Take take)
{
    DeviceAccess::of(device, "Renderer");
    check_options(options);
    error_boundary("making a Renderer", [&] {
        m.device = std::move(device);
        m.options = options;
        take(m.scene);
        m.queue = m.dev().make_queue();
        // A plain scene is checked against the device now (errors surface here) and uploaded when
        // a path that reads it first runs (raster, brute, shading): the ray path's BVH holds its
        // own copy of the triangles, so a ray-only Renderer never holds both (issue 37). One with
        // instances: its expansion likewise.
        for (const Scene::Mesh& item : m.scene.meshes()) m.instanced |= item.prototype != Scene::no_prototype;
        if (!m.instanced) m.check_scene_fits();
    });
}

} // namespace

Renderer::Renderer(Device device, const Scene& scene, RenderOptions options) : impl_(std::make_unique<Impl>())
{
    make_renderer(*impl_, device, options, [&](Scene& mine) { mine = scene; });
}

Renderer::Renderer(Device device, Scene&& scene, RenderOptions options) : impl_(std::make_unique<Impl>())
{
    // Swapped out, so that the caller's Scene is left empty (no cached expansion left claiming
    // to be valid) whatever Scene's own move leaves behind.
    make_renderer(*impl_, device, options, [&](Scene& mine) {
        mine = std::move(scene);
        scene = Scene();
    });
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

Renderer::Impl& Renderer::checked(const char* call) const
{
    if (!impl_)
        throw Error(Error::Kind::InvalidArgument, std::string(call) + ": the Renderer was moved from");
    return *impl_;
}

void Renderer::prepare(Path path)
{
    Impl& m = checked("Renderer::prepare");
    error_boundary(std::string("preparing the ") + to_string(path) + " path", [&] { m.prepare(path); });
}

VisibilityBuffer Renderer::render(const Camera& camera, int width, int height, Path path)
{
    Impl& m = checked("Renderer::render");
    camera.validate();
    Region region = m.options.region;
    if (region.whole()) region = Region{0, 0, width, height};
    check_region(region, width, height);
    return error_boundary(std::string("rendering with the ") + to_string(path) + " path", [&] {
        VisibilityBuffer target(m.device, region.width, region.height, m.options.samples, m.options.layers);
        m.render(camera, width, height, region, path, target);
        return target;
    });
}

void Renderer::render(const Camera& camera, Path path, VisibilityBuffer& target)
{
    Impl& m = checked("Renderer::render");
    camera.validate();
    if (!m.options.region.whole())
        throw Error(Error::Kind::InvalidArgument,
                    "Renderer::render: options().region needs the image's size; pass it with the region");
    error_boundary(std::string("rendering with the ") + to_string(path) + " path", [&] {
        Region whole{0, 0, target.width(), target.height()};
        m.render(camera, target.width(), target.height(), whole, path, target);
    });
}

void Renderer::render(const Camera& camera, int width, int height, const Region& region, Path path,
                      VisibilityBuffer& target)
{
    Impl& m = checked("Renderer::render");
    camera.validate();
    check_region(region, width, height);
    error_boundary(std::string("rendering with the ") + to_string(path) + " path",
                   [&] { m.render(camera, width, height, region, path, target); });
}

void Renderer::Impl::render(const Camera& camera, int width, int height, const Region& region, Path path,
                            VisibilityBuffer& target)
{
    if (target.empty()) throw Error(Error::Kind::InvalidArgument, "Renderer::render: empty target buffer");
    if (target.device().context() != device.context())
        throw Error(Error::Kind::InvalidArgument, "Renderer::render: the target belongs to another OpenCL context");
    if (target.width() != region.width || target.height() != region.height)
        throw Error(Error::Kind::InvalidArgument, "Renderer::render: the target is " + std::to_string(target.width()) +
                                                      "x" + std::to_string(target.height()) + ", the region " +
                                                      std::to_string(region.width) + "x" +
                                                      std::to_string(region.height));
    if (target.samples() != options.samples)
        throw Error(Error::Kind::InvalidArgument, "Renderer::render: the target holds " +
                                                      std::to_string(target.samples()) +
                                                      " sample(s) per pixel, the options ask for " +
                                                      std::to_string(options.samples));
    if (target.layers() != options.layers)
        throw Error(Error::Kind::InvalidArgument, "Renderer::render: the target holds " +
                                                      std::to_string(target.layers()) +
                                                      " layer(s), the options ask for " + std::to_string(options.layers));
    Frame frame;
    frame.layers = options.layers;
    frame.queue = queue;
    frame.width = region.width;
    frame.height = region.height;
    frame.region = clvis_region{region.x, region.y, region.width, region.height};
    frame.gpu_camera = make_gpu_camera(camera, width, height);
    frame.gpu_camera.sample_log2 = samples_log2(options.samples);
    frame.keys = cl::Buffer(target.keys(), true);
    frame.stages = &stages;
    // Build what the path needs before the clock starts: the frame is only its kernels.
    prepare(path);
    try {
        auto t0 = std::chrono::steady_clock::now();
        if (path == Path::Raster && instanced) raster->render(item_buffers(), frame, raster_chunk);
        else if (path == Path::Raster) raster->render(scene_buffers(), frame);
        else if (path == Path::Brute) render_brute(frame);
        else ray->render(gpu, frame, false);
        queue.finish();
        auto t1 = std::chrono::steady_clock::now();
        last.frame_ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
        std::optional<std::vector<StageTiming>> measured = stages.collect();
        last.stages_measured = measured.has_value();
        last.stages = measured ? std::move(*measured) : std::vector<StageTiming>{};
        last.raster_atomics = raster_depth_test(path);
    } catch (const cl::Error& e) {
        stages.collect();
        throw_cl_error(e, std::string("rendering with the ") + to_string(path) + " path");
    }
}

void Renderer::Impl::render_brute(Frame& frame)
{
    if (instanced) ray->render_brute(item_buffers(), frame);
    else ray->render(scene_buffers(), frame, true);
}

void Renderer::update(const Scene& scene)
{
    Impl& m = checked("Renderer::update");
    error_boundary("updating the Renderer's scene", [&] { m.update(scene); });
}

void Renderer::Impl::update(const Scene& now_scene)
{
    Impl& m = *this;
    const auto& old = m.scene.meshes();
    const auto& now = now_scene.meshes();
    if (old.size() != now.size())
        throw Error(Error::Kind::InvalidArgument, "Renderer::update: the scene has " + std::to_string(now.size()) +
                                                      " meshes, the renderer " + std::to_string(old.size()) +
                                                      "; make a new Renderer for a new scene");
    // Each prototype compared once, not once per instance (10,000 instances of one mesh).
    const auto& old_protos = m.scene.prototypes();
    const auto& now_protos = now_scene.prototypes();
    std::vector<char> proto_same(now_protos.size(), 0);
    for (std::size_t p = 0; p < now_protos.size() && p < old_protos.size(); ++p)
        proto_same[p] = now_protos[p].positions == old_protos[p].positions && now_protos[p].indices == old_protos[p].indices;
    std::vector<std::size_t> changed;
    for (std::size_t i = 0; i < now.size(); ++i) {
        bool instance = now[i].prototype != Scene::no_prototype;
        if (instance ? (now[i].prototype != old[i].prototype || !proto_same[now[i].prototype])
                     : (old[i].prototype != Scene::no_prototype || now[i].data.vertex_count() != old[i].data.vertex_count() ||
                        now[i].data.indices != old[i].data.indices))
            throw Error(Error::Kind::InvalidArgument, "Renderer::update: mesh " + std::to_string(i) +
                                                          " changed its topology or prototype; make a new Renderer");
        if ((!instance && now[i].data.positions != old[i].data.positions) || now[i].transform.m != old[i].transform.m)
            changed.push_back(i);
    }
    if (changed.empty()) return;
    for (std::size_t i : changed) {
        if (now[i].prototype == Scene::no_prototype)
            m.scene.set_positions(i, now[i].data.positions.data(), now[i].data.vertex_count());
        m.scene.set_transform(i, now[i].transform);
    }
    std::size_t first = 0;
    for (std::size_t i = 0, c = 0; i < now.size(); ++i) {
        std::size_t vertices = m.scene.data_of(i).vertex_count();
        if (c < changed.size() && changed[c] == i) {
            if (m.uploaded) m.upload_positions(i, first);
            ++c;
        }
        first += vertices;
    }
    m.items_uploaded = false; // uploaded again when next drawn: records are a few dozen bytes per item
    if (m.ray && m.ray->built()) m.ray->update(m.scene, m.queue);
}

namespace detail {

void set_raster_chunk(Renderer& renderer, std::size_t triangles)
{
    RendererAccess::of(renderer, "set_raster_chunk").raster_chunk = std::max<std::size_t>(triangles, 1);
}

bool expansion_uploaded(Renderer& renderer) { return RendererAccess::of(renderer, "expansion_uploaded").uploaded; }

std::uint64_t item_device_bytes(Renderer& renderer)
{
    Renderer::Impl& m = RendererAccess::of(renderer, "item_device_bytes");
    return m.items_uploaded ? m.items.device_bytes : 0;
}

} // namespace detail

const FrameTiming& Renderer::last_frame() const { return checked("Renderer::last_frame").last; }
const BvhStats& Renderer::bvh_stats() const
{
    const Impl& m = checked("Renderer::bvh_stats");
    return m.ray ? m.ray->stats() : m.no_bvh;
}
const RenderOptions& Renderer::options() const { return checked("Renderer::options").options; }
const RasterMappingChoice& Renderer::raster_mapping()
{
    Impl& m = checked("Renderer::raster_mapping");
    return error_boundary("choosing the raster mapping", [&]() -> const RasterMappingChoice& { return m.raster_mapping(); });
}
const RayMappingChoice& Renderer::ray_mapping()
{
    Impl& m = checked("Renderer::ray_mapping");
    return error_boundary("choosing the ray mapping", [&]() -> const RayMappingChoice& { return m.ray_mapping(); });
}
const Device& Renderer::device() const { return checked("Renderer::device").device; }

} // namespace clvis
