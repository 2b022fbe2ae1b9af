// clvis bench --rays: the ray-query workloads of issue #17 against Embree 3 in the same run:
// ambient occlusion rays from visibility buffers (the bunny, a 1M-triangle sphere; 8 per pixel at
// 960x540) and uniform random rays through a 1M-triangle soup. clvis answers rays resident on the
// device (RayQuery on cl_mem); Embree traces the same rays from host memory with rtcIntersect1 /
// rtcOccluded1 and their 16-wide forms. Also clvis's all hits (the 4 nearest hits and the count of
// each ray, RayQuery::all: host arrays in and out, transfers included), which Embree's queries do not
// answer; no Open3D workload runs here (its list_intersections is not compared). Writes
// bench-rays.json and bench-rays.csv.
#include "bench.hpp"
#include "bench_stats.hpp"
#include "bench_views.hpp"
#include "reference.hpp"

#include <clvis/clvis.hpp>

#include <CL/cl.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <random>

namespace clvis::bench {

namespace {

namespace fs = std::filesystem;

/// Issue #17's targets: clvis time / Embree single-ray time, per query.
constexpr double target_over_embree1 = 1.0;
/// Hits kept per ray by the all-hits timing.
constexpr int all_hits_k = 4;

struct Workload {
    std::string name;
    Scene scene;
    std::vector<RayRecord> rays;
};

struct Timing {
    std::string renderer; ///< clvis-closest, clvis-any, embree-intersect1, ...
    std::vector<double> ms;
    std::size_t rays = 0;
    double agree = -1; ///< fraction of rays whose answer equals clvis's (references only)
    std::string error;

    double median() const { return ms.empty() ? 0 : median_of(ms); }
    double mrays() const { return ms.empty() ? 0 : double(rays) / (median() * 1e3); }
};

/// The valid AO rays of `scene` seen by its framing camera at w x h.
std::vector<RayRecord> ao_rays(const Device& device, const Scene& scene, int w, int h, int per_pixel)
{
    Renderer renderer(device, scene);
    Camera camera = Camera::framing(scene.bounds());
    VisibilityBuffer vis = renderer.render(camera, w, h, Path::Ray);
    RayQuery query(renderer);
    AoOptions o;
    o.rays = per_pixel;
    std::vector<RayRecord> all = query.ambient_occlusion_rays(vis, camera, o), valid;
    valid.reserve(all.size());
    for (const RayRecord& r : all)
        if (ray_is_valid(r)) valid.push_back(r);
    return valid;
}

/// Uniform random rays: origins in the unit cube, directions uniform on the sphere, unbounded.
std::vector<RayRecord> random_rays(std::size_t n, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0, 1), s(-1, 1);
    std::vector<RayRecord> out(n);
    for (RayRecord& r : out) {
        float d[3], len2;
        do {
            for (float& x : d) x = s(rng);
            len2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        } while (len2 > 1 || len2 < 1e-4f);
        r = RayRecord{u(rng), u(rng), u(rng), 0, d[0], d[1], d[2], std::numeric_limits<float>::infinity()};
    }
    return out;
}

/// clvis on device-resident rays: one warm-up, then `repeats` timed calls; answers of the last.
Timing time_clvis(RayQuery& q, const Device& device, const std::vector<RayRecord>& rays, RayQueryKind kind,
                  int repeats, std::vector<HitRecord>& hits, std::vector<std::uint8_t>& flags)
{
    Timing t;
    t.renderer = std::string("clvis-") + to_string(kind);
    t.rays = rays.size();
    cl_int err = 0;
    cl_mem in = clCreateBuffer(device.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, rays.size() * sizeof(RayRecord),
                               const_cast<RayRecord*>(rays.data()), &err);
    std::size_t out_bytes = rays.size() * (kind == RayQueryKind::Closest ? sizeof(HitRecord) : 1);
    cl_mem out = err == CL_SUCCESS ? clCreateBuffer(device.context(), CL_MEM_READ_WRITE, out_bytes, nullptr, &err) : nullptr;
    if (err != CL_SUCCESS) {
        if (in) clReleaseMemObject(in);
        t.error = "cannot allocate the device buffers of " + std::to_string(rays.size()) + " rays";
        return t;
    }
    DeviceRays dr{in, RayLayout::AoS, rays.size(), 0};
    DeviceResults res{out, RayLayout::AoS, 0};
    for (int r = 0; r <= repeats; ++r) {
        RayQueryStats s = kind == RayQueryKind::Closest ? q.closest(dr, res) : q.occluded(dr, res);
        if (r > 0) t.ms.push_back(s.wall_ms);
    }
    void* host = kind == RayQueryKind::Closest ? static_cast<void*>(hits.data()) : static_cast<void*>(flags.data());
    clEnqueueReadBuffer(device.queue(), out, CL_TRUE, 0, out_bytes, host, 0, nullptr, nullptr);
    clReleaseMemObject(in);
    clReleaseMemObject(out);
    return t;
}

/// clvis all hits (all_hits_k per ray and the counts) from host arrays into host arrays (its only
/// form): one warm-up, then `repeats` timed calls, wall time with the transfers.
Timing time_clvis_all(RayQuery& q, const std::vector<RayRecord>& rays, int repeats)
{
    Timing t;
    t.renderer = "clvis-all" + std::to_string(all_hits_k);
    t.rays = rays.size();
    std::vector<HitRecord> hits(rays.size() * std::size_t(all_hits_k));
    std::vector<std::uint32_t> counts(rays.size());
    for (int r = 0; r <= repeats; ++r) {
        RayQueryStats s = q.all({rays.data(), rays.size()}, all_hits_k, hits.data(), counts.data());
        if (r > 0) t.ms.push_back(s.wall_ms);
    }
    return t;
}

std::vector<Timing> run_workload(const Device& device, const Workload& w, int repeats, int threads)
{
    std::vector<Timing> out;
    std::vector<HitRecord> hits(w.rays.size());
    std::vector<std::uint8_t> flags(w.rays.size());
    {
        Renderer renderer(device, w.scene);
        RayQuery q(renderer);
        out.push_back(time_clvis(q, device, w.rays, RayQueryKind::Closest, repeats, hits, flags));
        out.push_back(time_clvis(q, device, w.rays, RayQueryKind::Any, repeats, hits, flags));
        out.push_back(time_clvis_all(q, w.rays, repeats));
    }
    std::optional<EmbreeReference> embree;
    std::string error;
    try {
        embree.emplace(w.scene, threads);
    } catch (const std::exception& e) {
        error = e.what();
    }
    for (auto mode : {EmbreeMode::Single, EmbreeMode::Packet16})
        for (bool occluded : {false, true}) {
            Timing t;
            t.renderer = std::string("embree-") + (occluded ? "occluded" : "intersect") +
                         (mode == EmbreeMode::Single ? "1" : "16");
            t.rays = w.rays.size();
            t.error = error;
            if (!embree) {
                out.push_back(t);
                continue;
            }
            EmbreeRays e = embree->trace(w.rays.data(), w.rays.size(), occluded, mode, repeats);
            t.ms = e.run_ms;
            std::size_t same = 0;
            for (std::size_t i = 0; i < w.rays.size(); ++i)
                same += occluded ? e.occluded[i] == flags[i] : e.ids[i] == hits[i].id;
            t.agree = w.rays.empty() ? 1 : double(same) / double(w.rays.size());
            out.push_back(t);
        }
    return out;
}

const Timing* find(const std::vector<Timing>& ts, const std::string& name)
{
    for (const Timing& t : ts)
        if (t.renderer == name && t.error.empty() && !t.ms.empty()) return &t;
    return nullptr;
}

/// clvis time over the reference's (medians); nullopt when either is missing.
std::optional<double> ratio(const std::vector<Timing>& ts, const std::string& clvis, const std::string& ref)
{
    const Timing *a = find(ts, clvis), *b = find(ts, ref);
    if (!a || !b) return std::nullopt;
    return a->median() / b->median();
}

/// Runs bench/plot_rays.py on the JSON just written; a missing script or matplotlib is said, not fatal.
void plot(const fs::path& out_dir)
{
    fs::path script = fs::path("bench") / "plot_rays.py";
    std::error_code ec;
#ifdef CLVIS_BENCH_SOURCE_DIR
    if (!fs::is_regular_file(script, ec)) script = fs::path(CLVIS_BENCH_SOURCE_DIR) / "bench" / "plot_rays.py";
#endif
    std::string cmd = "/usr/bin/python3 '" + script.string() + "' '" + (out_dir / "bench-rays.json").string() + "' '" +
                      out_dir.string() + "'";
    if (std::system(cmd.c_str()) != 0) std::fprintf(stderr, "clvis bench --rays: the plot failed (%s)\n", cmd.c_str());
}

nlohmann::json optional_json(std::optional<double> v) { return v ? nlohmann::json(*v) : nlohmann::json(nullptr); }

} // namespace

void run_ray_bench(const BenchConfig& config, const Device& device)
{
    auto t_start = std::chrono::steady_clock::now();
    fs::path out_dir(config.out);
    fs::create_directories(out_dir);
    int w = config.quick ? 480 : 960, h = config.quick ? 270 : 540, per_pixel = config.quick ? 4 : 8;
    std::size_t big = config.quick ? 100000 : 1000000, random_count = config.quick ? 200000 : 2000000;
    int repeats = config.frames > 0 ? config.frames : 3;
    std::string bunny = bundled_mesh("stanford-bunny.obj");

    std::vector<Workload> workloads;
    workloads.push_back({"ao-bunny", load_scene({bunny}), {}});
    {
        Scene s;
        s.add_mesh(make_uv_sphere(big));
        workloads.push_back({"ao-sphere", std::move(s), {}});
        Scene soup;
        soup.add_mesh(make_soup(big, 1));
        workloads.push_back({"random-soup", std::move(soup), random_rays(random_count, 2)});
    }
    for (std::size_t i = 0; i < 2; ++i) workloads[i].rays = ao_rays(device, workloads[i].scene, w, h, per_pixel);

    nlohmann::json j{{"device", device.info().name}, {"threads", config.ref_threads}, {"repeats", repeats},
                     {"ao", {{"width", w}, {"height", h}, {"rays_per_pixel", per_pixel}}},
                     {"target_over_embree1", target_over_embree1}, {"workloads", nlohmann::json::array()}};
    std::ofstream csv(out_dir / "bench-rays.csv");
    csv << "workload,triangles,rays,renderer,median_ms,mrays_per_s,agree,error\n";
    std::printf("%-12s %9s %9s  %-20s %10s %9s %8s %7s\n", "workload", "triangles", "rays", "renderer", "median ms",
                "Mrays/s", "vs emb1", "agree");
    for (const Workload& wl : workloads) {
        std::vector<Timing> ts = run_workload(device, wl, repeats, config.ref_threads);
        nlohmann::json wj{{"name", wl.name}, {"triangles", wl.scene.triangle_count()}, {"rays", wl.rays.size()},
                          {"closest_over_intersect1", optional_json(ratio(ts, "clvis-closest", "embree-intersect1"))},
                          {"any_over_occluded1", optional_json(ratio(ts, "clvis-any", "embree-occluded1"))},
                          {"closest_over_intersect16", optional_json(ratio(ts, "clvis-closest", "embree-intersect16"))},
                          {"any_over_occluded16", optional_json(ratio(ts, "clvis-any", "embree-occluded16"))},
                          {"runs", nlohmann::json::array()}};
        for (const Timing& t : ts) {
            wj["runs"].push_back({{"renderer", t.renderer}, {"ms", t.ms}, {"median_ms", t.median()},
                                  {"mrays_per_s", t.mrays()}, {"agree", t.agree}, {"error", t.error}});
            csv << wl.name << ',' << wl.scene.triangle_count() << ',' << wl.rays.size() << ',' << t.renderer << ','
                << t.median() << ',' << t.mrays() << ',' << t.agree << ",\"" << t.error << "\"\n";
            std::optional<double> r;
            if (t.renderer == "clvis-closest") r = ratio(ts, "clvis-closest", "embree-intersect1");
            if (t.renderer == "clvis-any") r = ratio(ts, "clvis-any", "embree-occluded1");
            char rbuf[16] = "", abuf[16] = "";
            if (r) std::snprintf(rbuf, sizeof rbuf, "%.2f", *r);
            if (t.agree >= 0) std::snprintf(abuf, sizeof abuf, "%.5f", t.agree);
            std::printf("%-12s %9zu %9zu  %-20s %10.1f %9.2f %8s %7s%s%s\n", wl.name.c_str(), wl.scene.triangle_count(),
                        wl.rays.size(), t.renderer.c_str(), t.median(), t.mrays(), rbuf, abuf,
                        t.error.empty() ? "" : "  ", t.error.c_str());
        }
        j["workloads"].push_back(wj);
    }
    j["total_s"] = ms_since(t_start) / 1000;
    std::ofstream(out_dir / "bench-rays.json") << j.dump(2) << "\n";
    if (!config.no_plot) plot(out_dir);
    std::printf("\nclvis bench --rays: %.1f s on %s (Embree on %d threads); vs emb1 = clvis time / rtcIntersect1 or "
                "rtcOccluded1 time (target <= %.1f); wrote %s\n",
                ms_since(t_start) / 1000, device.info().name.c_str(), config.ref_threads, target_over_embree1,
                (out_dir / "bench-rays.json").string().c_str());
}

} // namespace clvis::bench
