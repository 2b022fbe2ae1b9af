// Embree 3 reference: builds the scene once per EmbreeReference, then traces the primary rays of
// CONVENTIONS.md for every pixel centre. Work is split into 16x16 pixel tiles taken from an atomic
// counter by `threads` std::threads; Embree's own threads (TBB) only build.
#include "reference_embree.hpp"
#if CLVIS_HAVE_EMBREE
#include "pinned_threads.hpp"
#include "reference_embree_rays.hpp"
#endif

#include <clvis/scene.hpp>

#include <stdexcept>

#if CLVIS_HAVE_EMBREE

#include <embree3/rtcore.h>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace clvis::bench {

namespace {

/// Pixels per side of the unit of work a thread takes; a multiple of the 4x4 packet tile.
constexpr int work_tile = 16;
/// Pixels per side of one rtcIntersect16 packet.
constexpr int packet_side = 4;

const char* error_name(RTCError e)
{
    switch (e) {
    case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN: return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
    }
    return "RTC_ERROR_?";
}

void check(RTCDevice device, const char* call)
{
    RTCError e = rtcGetDeviceError(device);
    if (e != RTC_ERROR_NONE) throw std::runtime_error(std::string("embree: ") + call + ": " + error_name(e));
}

/// Embree asks every tracing thread for flush-to-zero and denormals-are-zero (its verbose mode
/// warns of a severe slowdown without them); the caller's mode is restored on leaving.
class DenormalsOff {
public:
#if defined(__SSE__)
    DenormalsOff() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | ftz_daz); }
    ~DenormalsOff() { _mm_setcsr(saved_); }

private:
    static constexpr unsigned ftz_daz = 0x8040; // MXCSR bits 15 (FTZ) and 6 (DAZ)
    unsigned saved_;
#endif
};

/// The primary rays of CONVENTIONS.md in float, computed from the double-precision camera.
struct RayGen {
    bool ortho = false;
    Vec3 eye, r, u, f;
    Intrinsics k; ///< screen -> raster map
    int width = 0, height = 0;
    float tnear = 0, tfar = 0;

    RayGen(const Camera& camera, int w, int h) : width(w), height(h)
    {
        camera.validate();
        CameraFrame fr = camera.frame();
        k = camera.raster_map(w, h);
        ortho = camera.projection == Projection::Orthographic;
        eye = camera.eye;
        r = fr.r;
        u = fr.u;
        f = fr.f;
        tnear = float(camera.near);
        tfar = float(camera.far);
    }

    /// Origin and direction of the ray through the centre of pixel (i, j).
    void at(int i, int j, float org[3], float dir[3]) const
    {
        double sx = (i + 0.5 - k.cx) / k.fx;
        double sy = (k.cy - (j + 0.5)) / k.fy;
        Vec3 o = eye, d = f;
        if (ortho) o = eye + r * sx + u * sy;
        else d = r * sx + u * sy + f;
        org[0] = float(o.x), org[1] = float(o.y), org[2] = float(o.z);
        dir[0] = float(d.x), dir[1] = float(d.y), dir[2] = float(d.z);
    }
};

struct Frame {
    std::uint32_t* ids;
    float* depth;
};

void trace_tile_single(RTCScene scene, const RayGen& gen, int x0, int y0, Frame out)
{
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    int x1 = std::min(x0 + work_tile, gen.width), y1 = std::min(y0 + work_tile, gen.height);
    for (int j = y0; j < y1; ++j)
        for (int i = x0; i < x1; ++i) {
            RTCRayHit rh;
            float org[3], dir[3];
            gen.at(i, j, org, dir);
            rh.ray.org_x = org[0], rh.ray.org_y = org[1], rh.ray.org_z = org[2];
            rh.ray.dir_x = dir[0], rh.ray.dir_y = dir[1], rh.ray.dir_z = dir[2];
            rh.ray.tnear = gen.tnear;
            rh.ray.tfar = gen.tfar;
            rh.ray.time = 0;
            rh.ray.mask = 0xFFFFFFFFu;
            rh.ray.id = 0;
            rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(scene, &context, &rh);
            std::size_t p = std::size_t(j) * gen.width + i;
            bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            out.ids[p] = hit ? rh.hit.primID : background_id;
            out.depth[p] = hit ? rh.ray.tfar : std::numeric_limits<float>::infinity();
        }
}

void trace_tile_packets(RTCScene scene, const RayGen& gen, int x0, int y0, Frame out)
{
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    int x1 = std::min(x0 + work_tile, gen.width), y1 = std::min(y0 + work_tile, gen.height);
    for (int py = y0; py < y1; py += packet_side)
        for (int px = x0; px < x1; px += packet_side) {
            for (int k = 0; k < 16; ++k) {
                int i = px + k % packet_side, j = py + k / packet_side;
                bool inside = i < gen.width && j < gen.height;
                valid[k] = inside ? -1 : 0;
                float org[3], dir[3];
                gen.at(inside ? i : px, inside ? j : py, org, dir);
                rh.ray.org_x[k] = org[0], rh.ray.org_y[k] = org[1], rh.ray.org_z[k] = org[2];
                rh.ray.dir_x[k] = dir[0], rh.ray.dir_y[k] = dir[1], rh.ray.dir_z[k] = dir[2];
                rh.ray.tnear[k] = gen.tnear;
                rh.ray.tfar[k] = gen.tfar;
                rh.ray.time[k] = 0;
                rh.ray.mask[k] = 0xFFFFFFFFu;
                rh.ray.id[k] = unsigned(k);
                rh.ray.flags[k] = 0;
                rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.primID[k] = RTC_INVALID_GEOMETRY_ID;
                rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
            }
            rtcIntersect16(valid, scene, &context, &rh);
            for (int k = 0; k < 16; ++k) {
                if (!valid[k]) continue;
                int i = px + k % packet_side, j = py + k / packet_side;
                std::size_t p = std::size_t(j) * gen.width + i;
                bool hit = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
                out.ids[p] = hit ? rh.hit.primID[k] : background_id;
                out.depth[p] = hit ? rh.ray.tfar[k] : std::numeric_limits<float>::infinity();
            }
        }
}

} // namespace

struct EmbreeReference::Impl {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    int threads = 2;
    std::vector<double> builds_ms;

    ~Impl()
    {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }

    /// A fresh scene of one triangle geometry (geomID 0), committed; returns the commit's time.
    double build(const Scene& s)
    {
        RTCScene next = rtcNewScene(device);
        check(device, "rtcNewScene");
        rtcSetSceneFlags(next, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(next, RTC_BUILD_QUALITY_HIGH);
        RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
        check(device, "rtcNewGeometry");
        rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
        const std::vector<float>& positions = s.world_positions();
        const std::vector<std::uint32_t>& indices = s.world_indices();
        // Embree's own buffers: it pads them for its 16-byte loads past the last element.
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                              3 * sizeof(float), s.vertex_count()));
        auto* t = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
            geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t), s.triangle_count()));
        check(device, "rtcSetNewGeometryBuffer");
        std::memcpy(v, positions.data(), positions.size() * sizeof(float));
        std::memcpy(t, indices.data(), indices.size() * sizeof(std::uint32_t));
        rtcCommitGeometry(geometry);
        rtcAttachGeometryByID(next, geometry, 0);
        rtcReleaseGeometry(geometry);
        check(device, "rtcAttachGeometryByID");
        auto t0 = std::chrono::steady_clock::now();
        rtcCommitScene(next);
        double ms = ms_since(t0);
        check(device, "rtcCommitScene");
        if (scene) rtcReleaseScene(scene);
        scene = next;
        return ms;
    }
};

EmbreeReference::EmbreeReference(const Scene& scene, int threads, int builds) : impl_(std::make_unique<Impl>())
{
    if (threads < 1 || builds < 1) throw std::runtime_error("embree: threads and builds must be >= 1");
    if (scene.empty()) throw std::runtime_error("embree: the scene holds no triangles");
    impl_->threads = threads;
    std::string config = "threads=" + std::to_string(threads);
    impl_->device = rtcNewDevice(config.c_str());
    if (!impl_->device) throw std::runtime_error(std::string("embree: rtcNewDevice: ") + error_name(rtcGetDeviceError(nullptr)));
    for (int b = 0; b < builds; ++b) impl_->builds_ms.push_back(impl_->build(scene));
}

EmbreeReference::~EmbreeReference() = default;

double EmbreeReference::build_ms() const { return median_of(impl_->builds_ms); }
const std::vector<double>& EmbreeReference::build_samples_ms() const { return impl_->builds_ms; }

std::string EmbreeReference::description() const
{
    return "Embree " + std::to_string(RTC_VERSION_MAJOR) + "." + std::to_string(RTC_VERSION_MINOR) + "." +
           std::to_string(RTC_VERSION_PATCH) + " (threads=" + std::to_string(impl_->threads) + ")";
}

double EmbreeReference::rebuild(const Scene& scene)
{
    double ms = impl_->build(scene);
    impl_->builds_ms.push_back(ms);
    return ms;
}

namespace {

/// What a view traces: the reference's scene as it was made (a rebuild releases it), its device
/// and threads, and its timed builds.
struct Traced {
    RTCDevice device;
    RTCScene scene;
    int threads;
    const std::vector<double>& builds_ms;
};

class EmbreeView final : public ReferenceView {
public:
    EmbreeView(const Traced& r, const Camera& camera, int width, int height, EmbreeMode m)
        : ref_(r), gen_(camera, width, height), mode_(m), tiles_x_((width + work_tile - 1) / work_tile),
          tiles_(tiles_x_ * ((height + work_tile - 1) / work_tile))
    {
        result_.name = mode_ == EmbreeMode::Single ? "embree-intersect1" : "embree-intersect16";
        result_.width = width;
        result_.height = height;
        result_.ids.assign(std::size_t(width) * height, background_id);
        result_.depth.assign(result_.ids.size(), std::numeric_limits<float>::infinity());
        trace(); // warm-up: first touches of the BVH and the buffers
        check(ref_.device, "rtcIntersect");
    }

    const ReferenceResult& result() override
    {
        check(ref_.device, "rtcIntersect");
        result_.build_samples_ms = ref_.builds_ms;
        result_.build_ms = median_of(ref_.builds_ms);
        return result_;
    }

private:
    Traced ref_;
    RayGen gen_;
    EmbreeMode mode_;
    int tiles_x_, tiles_;

    void render_frame() override { trace(); }

    /// Every pixel centre traced once by `threads` std::threads taking tiles from a counter.
    void trace()
    {
        Frame out{result_.ids.data(), result_.depth.data()};
        std::atomic<int> next{0};
        auto worker = [&] {
            DenormalsOff denormals_off;
            for (int t = next++; t < tiles_; t = next++) {
                int x0 = t % tiles_x_ * work_tile, y0 = t / tiles_x_ * work_tile;
                if (mode_ == EmbreeMode::Single) trace_tile_single(ref_.scene, gen_, x0, y0, out);
                else trace_tile_packets(ref_.scene, gen_, x0, y0, out);
            }
        };
        run_pinned(ref_.threads, worker);
    }
};

} // namespace

std::unique_ptr<ReferenceView> EmbreeReference::view(const Camera& camera, int width, int height, EmbreeMode mode)
{
    if (width <= 0 || height <= 0) throw std::runtime_error("embree: image size must be positive");
    return std::make_unique<EmbreeView>(Traced{impl_->device, impl_->scene, impl_->threads, impl_->builds_ms}, camera,
                                        width, height, mode);
}

ReferenceResult EmbreeReference::render(const Camera& camera, int width, int height, EmbreeMode mode, int repeats,
                                        double budget_ms)
{
    std::unique_ptr<ReferenceView> v = view(camera, width, height, mode);
    std::vector<double> ms;
    while (!enough_frames(ms, repeats, budget_ms)) ms.push_back(v->frame());
    return v->result();
}

EmbreeRays EmbreeReference::trace(const RayRecord* rays, std::size_t n, bool occluded, EmbreeMode mode, int repeats)
{
    EmbreeRays r = trace_embree_rays(impl_->scene, impl_->threads, rays, n, occluded, mode, repeats);
    check(impl_->device, occluded ? "rtcOccluded" : "rtcIntersect");
    return r;
}

bool embree_available() noexcept { return true; }

} // namespace clvis::bench

#else // !CLVIS_HAVE_EMBREE

// A deliberate twin of reference_gl.cpp's: each reference ends in the same pair, available() and a stub
// that reports it was not built, so the driver treats every reference alike.

namespace clvis::bench {

constexpr const char* not_built = "embree: clvis was built without Embree 3 (Debian: libembree-dev)";

struct EmbreeReference::Impl {};

EmbreeReference::EmbreeReference(const Scene&, int, int) { throw std::runtime_error(not_built); }
EmbreeReference::~EmbreeReference() = default;
double EmbreeReference::build_ms() const { return 0; }
const std::vector<double>& EmbreeReference::build_samples_ms() const
{
    static const std::vector<double> none;
    return none;
}
std::string EmbreeReference::description() const { return "Embree (not built)"; }
ReferenceResult EmbreeReference::render(const Camera&, int, int, EmbreeMode, int, double)
{
    throw std::runtime_error(not_built);
}
double EmbreeReference::rebuild(const Scene&) { throw std::runtime_error(not_built); }
std::unique_ptr<ReferenceView> EmbreeReference::view(const Camera&, int, int, EmbreeMode)
{
    throw std::runtime_error(not_built);
}
EmbreeRays EmbreeReference::trace(const RayRecord*, std::size_t, bool, EmbreeMode, int)
{
    throw std::runtime_error(not_built);
}
bool embree_available() noexcept { return false; }

} // namespace clvis::bench

#endif

namespace clvis::bench {

const char* to_string(EmbreeMode mode) noexcept
{
    return mode == EmbreeMode::Single ? "rtcIntersect1" : "rtcIntersect16";
}

ReferenceResult render_embree(const Scene& scene, const Camera& camera, int width, int height, EmbreeMode mode,
                              int repeats, int threads)
{
    try {
        EmbreeReference reference(scene, threads);
        return reference.render(camera, width, height, mode, repeats);
    } catch (const std::exception& e) {
        ReferenceResult failed;
        failed.name = mode == EmbreeMode::Single ? "embree-intersect1" : "embree-intersect16";
        failed.width = width;
        failed.height = height;
        failed.error = e.what();
        return failed;
    }
}

} // namespace clvis::bench
