// Rays made on the device from a visibility buffer (kernels/ray_generate.cl) and answered by the
// any-hit query (ray_query.cpp), in chunks of pixels so device memory stays bounded: ambient
// occlusion and shadows toward a point light, resolved per pixel on the host. Only covered pixels
// get rays: their indices, listed in row order from the keys the host reads anyway, are the
// generator's launch (a background pixel's value is 1 without a ray).
#include "query/ray_query_impl.hpp"
#include "render/sample_scene.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace clvis {

using namespace detail;

namespace {

/// Lifts ray origins off the surface by this fraction of the scene's diagonal (world units), so
/// that a ray does not meet its own triangle through the rounding of the visible point.
constexpr double surface_offset = 1e-4;

/// Throws unless `vis` can be read by `r`'s kernels.
void check_buffer(Renderer::Impl& r, const VisibilityBuffer& vis, const char* what)
{
    if (vis.empty()) throw Error(Error::Kind::InvalidArgument, std::string(what) + ": empty visibility buffer");
    if (vis.device().context() != r.device.context())
        throw Error(Error::Kind::InvalidArgument, std::string(what) + ": the buffer belongs to another OpenCL context");
    if (vis.samples() != 1)
        throw Error(Error::Kind::InvalidArgument, std::string(what) + ": rays start from one sample per pixel, the "
                                                                     "buffer holds " + std::to_string(vis.samples()));
}

double diagonal(const Scene& scene)
{
    Bounds b = scene.bounds();
    Vec3 d = b.hi - b.lo;
    double len = length(d);
    return std::isfinite(len) && len > 0 ? len : 1.0;
}

} // namespace

void RayQuery::Impl::reserve_generated(std::size_t rays)
{
    if (rays <= generated_capacity) return;
    r.dev().check_allocation(std::uint64_t(rays) * sizeof(RayRecord),
                             "a chunk of " + std::to_string(rays) + " generated rays");
    try {
        generated_rays = cl::Buffer(r.dev().context, CL_MEM_READ_WRITE, rays * sizeof(RayRecord));
        generated_flags = cl::Buffer(r.dev().context, CL_MEM_READ_WRITE, rays);
    } catch (const cl::Error& e) {
        throw_cl_error(e, "allocating " + std::to_string(rays) + " generated rays");
    }
    generated_capacity = rays;
}

/// Sets the arguments of a generator kernel that stay the same from chunk to chunk (its
/// arguments 9 to 11 are set by the caller, 12 (the list of covered pixels, or null) by its user). Returns the scene it reads (a scene with instances:
/// the keys' triangles, render/sample_scene.hpp), to be kept while the kernel runs.
static SampleScene bind_generator(RayQuery::Impl& m, cl::Kernel& generate, const VisibilityBuffer& vis,
                                  const clvis_camera_gpu& g, int per_pixel, const cl::Buffer& rays)
{
    Renderer::Impl& r = m.r;
    SampleScene scene = sample_scene(r, vis, true);
    generate.setArg(0, scene.keys);
    generate.setArg(1, sizeof g, &g);
    generate.setArg(2, scene.scene.positions);
    generate.setArg(3, scene.scene.indices);
    generate.setArg(6, cl_uint(per_pixel));
    generate.setArg(7, float(surface_offset * diagonal(r.scene)));
    generate.setArg(8, rays);
    return scene;
}

/// Enqueues the generation of the rays of pixel entries [first, first + n) (of the covered list
/// where one is set, else of the buffer).
static void generate_chunk(RayQuery::Impl& m, cl::Kernel& generate, std::size_t first, std::size_t n, int per_pixel)
{
    generate.setArg(4, cl_uint(first));
    generate.setArg(5, cl_uint(n));
    m.r.queue.enqueueNDRangeKernel(generate, cl::NullRange, cl::NDRange(round_up(n * std::size_t(per_pixel), 64)),
                                   cl::NDRange(64));
}

/// Pixels per chunk: options.batch_rays rays at most, at least one pixel.
static std::size_t chunk_pixels(const RayQuery::Impl& m, std::size_t pixels, int per_pixel)
{
    return std::min(pixels, std::max<std::size_t>(1, m.options.batch_rays / std::size_t(per_pixel)));
}

/// Generates `per_pixel` rays per pixel with `generate`, answers them with the any-hit query,
/// and averages the unoccluded rays.
static PixelRays pixel_rays(RayQuery::Impl& m, const VisibilityBuffer& vis, const Camera& camera, int per_pixel,
                            cl::Kernel& generate)
{
    auto t0 = std::chrono::steady_clock::now();
    Renderer::Impl& r = m.r;
    camera.validate();
    PixelRays out;
    out.width = vis.width();
    out.height = vis.height();
    std::size_t pixels = std::size_t(out.width) * std::size_t(out.height);
    out.value.assign(pixels, 1.0f);
    std::vector<std::uint64_t> keys = vis.read_keys();
    std::vector<std::uint32_t> covered; // the pixels that get rays, in row order
    covered.reserve(pixels);
    for (std::size_t p = 0; p < pixels; ++p)
        if (std::uint32_t(keys[p]) != background_id) covered.push_back(std::uint32_t(p));
    std::size_t chunk = chunk_pixels(m, std::max<std::size_t>(1, covered.size()), per_pixel);
    std::size_t chunk_rays = chunk * std::size_t(per_pixel);
    std::vector<std::uint8_t> flags(chunk_rays);
    try {
        m.reserve_generated(chunk_rays);
        const cl::Buffer &rays = m.generated_rays, &hit = m.generated_flags;
        cl::Buffer list;
        if (!covered.empty()) {
            list = cl::Buffer(r.dev().context, CL_MEM_READ_ONLY, covered.size() * sizeof(std::uint32_t));
            r.queue.enqueueWriteBuffer(list, CL_FALSE, 0, covered.size() * sizeof(std::uint32_t), covered.data());
            generate.setArg(12, list);
        }
        SampleScene scene =
            bind_generator(m, generate, vis, make_gpu_camera(camera, out.width, out.height), per_pixel, rays);
        for (std::size_t first = 0; first < covered.size(); first += chunk) {
            std::size_t n = std::min(chunk, covered.size() - first), n_rays = n * std::size_t(per_pixel);
            generate_chunk(m, generate, first, n, per_pixel);
            DeviceRays in{rays(), RayLayout::AoS, n_rays, 0};
            DeviceResults res{hit(), RayLayout::AoS, 0};
            RayQueryStats s = m.run(RayQueryKind::Any, m.source(in), m.device_sink(RayQueryKind::Any, res, n_rays));
            r.queue.enqueueReadBuffer(hit, CL_TRUE, 0, n_rays, flags.data());
            out.stats.rays += s.rays;
            out.stats.invalid += s.invalid;
            out.stats.batches += s.batches;
            out.stats.device_ms += s.device_ms;
            for (std::size_t p = 0; p < n; ++p) {
                int open = 0;
                for (int k = 0; k < per_pixel; ++k) open += flags[p * std::size_t(per_pixel) + std::size_t(k)] == 0;
                out.value[covered[first + p]] = float(open) / float(per_pixel);
            }
        }
    } catch (const cl::Error& e) {
        throw_cl_error(e, "generating rays from a visibility buffer");
    }
    out.stats.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
}

/// The AO generator with its per-call arguments set, the options checked.
static cl::Kernel& ao_generator(RayQuery::Impl& m, const VisibilityBuffer& vis, const AoOptions& options)
{
    check_buffer(m.r, vis, "ambient_occlusion");
    if (options.rays < 1 || options.rays > 1024)
        throw Error(Error::Kind::InvalidArgument,
                    "ambient_occlusion: rays per pixel must lie in [1, 1024], got " + std::to_string(options.rays));
    if (!std::isfinite(options.distance) || options.distance < 0)
        throw Error(Error::Kind::InvalidArgument, "ambient_occlusion: the distance must be finite and >= 0");
    float distance = options.distance > 0 ? options.distance : float(0.1 * diagonal(m.r.scene));
    if (!m.generate_ao()) m.generate_ao = cl::Kernel(m.r.dev().program("ray_generate"), "ray_generate_ao");
    m.generate_ao.setArg(9, distance);
    m.generate_ao.setArg(10, cl_uint(options.seed & 0xFFFFFFFFu));
    m.generate_ao.setArg(11, cl_uint(options.seed >> 32));
    return m.generate_ao;
}

PixelRays RayQuery::ambient_occlusion(const VisibilityBuffer& vis, const Camera& camera, const AoOptions& options)
{
    return error_boundary("ambient occlusion", [&] {
        return pixel_rays(*impl_, vis, camera, options.rays, ao_generator(*impl_, vis, options));
    });
}

std::vector<RayRecord> RayQuery::ambient_occlusion_rays(const VisibilityBuffer& vis, const Camera& camera,
                                                        const AoOptions& options)
{
    Impl& m = *impl_;
    camera.validate();
    return error_boundary("generating ambient occlusion rays", [&] {
        cl::Kernel& generate = ao_generator(m, vis, options);
        std::size_t pixels = std::size_t(vis.width()) * std::size_t(vis.height()), per = std::size_t(options.rays);
        std::size_t chunk = chunk_pixels(m, pixels, options.rays);
        m.reserve_generated(chunk * per);
        std::vector<RayRecord> out(pixels * per);
        clvis_camera_gpu g = make_gpu_camera(camera, vis.width(), vis.height());
        SampleScene scene = bind_generator(m, generate, vis, g, options.rays, m.generated_rays);
        generate.setArg(12, sizeof(cl_mem), nullptr); // every pixel, the background's too
        for (std::size_t first = 0; first < pixels; first += chunk) {
            std::size_t n = std::min(chunk, pixels - first);
            generate_chunk(m, generate, first, n, options.rays);
            m.r.queue.enqueueReadBuffer(m.generated_rays, CL_TRUE, 0, n * per * sizeof(RayRecord), &out[first * per]);
        }
        return out;
    });
}

PixelRays RayQuery::shadows(const VisibilityBuffer& vis, const Camera& camera, const Vec3& light)
{
    Impl& m = *impl_;
    check_buffer(m.r, vis, "shadows");
    if (!is_finite(light)) throw Error(Error::Kind::InvalidArgument, "shadows: the light position must be finite");
    return error_boundary("shadow rays", [&] {
        if (!m.generate_shadow()) m.generate_shadow = cl::Kernel(m.r.dev().program("ray_generate"), "ray_generate_shadow");
        m.generate_shadow.setArg(9, float(light.x));
        m.generate_shadow.setArg(10, float(light.y));
        m.generate_shadow.setArg(11, float(light.z));
        return pixel_rays(m, vis, camera, 1, m.generate_shadow);
    });
}

} // namespace clvis
