// Embree 3 on arbitrary rays: rtcIntersect1/rtcOccluded1 per ray, or rtcIntersect16/rtcOccluded16
// on 16 consecutive rays, over chunks taken from an atomic counter by `threads` std::threads, with
// incoherent-ray hints. The reference for clvis's ray queries (host/query/ray_query.cpp).
#include "reference_embree.hpp"

#if CLVIS_HAVE_EMBREE

#include "pinned_threads.hpp"
#include "reference_embree_rays.hpp"

#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include <atomic>
#include <chrono>
#include <limits>
#include <stdexcept>

namespace clvis::bench {

namespace {

/// Rays per unit of work a thread takes (a multiple of 16).
constexpr std::size_t chunk_rays = 4096;

struct Out {
    std::uint32_t* ids;
    float* t;
    std::uint8_t* occluded;
};

void fill_ray(RTCRay& r, const RayRecord& q)
{
    r.org_x = q.ox, r.org_y = q.oy, r.org_z = q.oz, r.tnear = q.tmin;
    r.dir_x = q.dx, r.dir_y = q.dy, r.dir_z = q.dz, r.tfar = q.tmax;
    r.time = 0, r.mask = 0xFFFFFFFFu, r.id = 0, r.flags = 0;
}

void trace_single(RTCScene scene, const RayRecord* rays, std::size_t first, std::size_t last, bool occluded, Out out)
{
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    for (std::size_t i = first; i < last; ++i) {
        if (occluded) {
            RTCRay r;
            fill_ray(r, rays[i]);
            rtcOccluded1(scene, &context, &r);
            out.occluded[i] = r.tfar == -std::numeric_limits<float>::infinity();
            continue;
        }
        RTCRayHit rh;
        fill_ray(rh.ray, rays[i]);
        rh.hit.geomID = rh.hit.primID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &context, &rh);
        bool hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        out.ids[i] = hit ? rh.hit.primID : background_id;
        out.t[i] = hit ? rh.ray.tfar : std::numeric_limits<float>::infinity();
    }
}

void fill_packet(RTCRay16& r, int valid[16], const RayRecord* rays, std::size_t i, std::size_t last)
{
    for (std::size_t k = 0; k < 16; ++k) {
        bool in = i + k < last;
        const RayRecord& q = rays[in ? i + k : i];
        valid[k] = in ? -1 : 0;
        r.org_x[k] = q.ox, r.org_y[k] = q.oy, r.org_z[k] = q.oz, r.tnear[k] = q.tmin;
        r.dir_x[k] = q.dx, r.dir_y[k] = q.dy, r.dir_z[k] = q.dz, r.tfar[k] = q.tmax;
        r.time[k] = 0, r.mask[k] = 0xFFFFFFFFu, r.id[k] = unsigned(k), r.flags[k] = 0;
    }
}

void trace_packets(RTCScene scene, const RayRecord* rays, std::size_t first, std::size_t last, bool occluded, Out out)
{
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    alignas(64) RTCRayHit16 rh;
    alignas(64) int valid[16];
    for (std::size_t i = first; i < last; i += 16) {
        fill_packet(rh.ray, valid, rays, i, last);
        if (occluded) {
            rtcOccluded16(valid, scene, &context, &rh.ray);
            for (std::size_t k = 0; k < 16 && i + k < last; ++k)
                out.occluded[i + k] = rh.ray.tfar[k] == -std::numeric_limits<float>::infinity();
            continue;
        }
        for (int k = 0; k < 16; ++k) rh.hit.geomID[k] = rh.hit.primID[k] = rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect16(valid, scene, &context, &rh);
        for (std::size_t k = 0; k < 16 && i + k < last; ++k) {
            bool hit = rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
            out.ids[i + k] = hit ? rh.hit.primID[k] : background_id;
            out.t[i + k] = hit ? rh.ray.tfar[k] : std::numeric_limits<float>::infinity();
        }
    }
}

} // namespace

EmbreeRays trace_embree_rays(RTCScene scene, int threads, const RayRecord* rays, std::size_t n, bool occluded,
                             EmbreeMode mode, int repeats)
{
    EmbreeRays result;
    if (occluded) result.occluded.assign(n, 0);
    else {
        result.ids.assign(n, background_id);
        result.t.assign(n, std::numeric_limits<float>::infinity());
    }
    Out out{result.ids.data(), result.t.data(), result.occluded.data()};
    std::size_t chunks = (n + chunk_rays - 1) / chunk_rays;
    auto run = [&] {
        std::atomic<std::size_t> next{0};
        auto worker = [&] {
#if defined(__SSE__)
            unsigned saved = _mm_getcsr();
            _mm_setcsr(saved | 0x8040); // flush-to-zero and denormals-are-zero, as Embree asks
#endif
            for (std::size_t c = next++; c < chunks; c = next++) {
                std::size_t first = c * chunk_rays, last = std::min(n, first + chunk_rays);
                if (mode == EmbreeMode::Single) trace_single(scene, rays, first, last, occluded, out);
                else trace_packets(scene, rays, first, last, occluded, out);
            }
#if defined(__SSE__)
            _mm_setcsr(saved);
#endif
        };
        run_pinned(threads, worker);
    };
    run(); // warm-up
    for (int r = 0; r < repeats; ++r) {
        auto t0 = std::chrono::steady_clock::now();
        run();
        result.run_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    return result;
}

} // namespace clvis::bench

#endif
