// clvis rays: a file of rays in, the answers of one ray query out (CONVENTIONS.md "Ray queries"):
// closest hits, occlusion flags, hit counts or all hits (up to --max-hits per ray, and with --counts
// the number of each ray's hits), as .npy or raw records by the file's extension.
#include "commands.hpp"
#include "options.hpp"
#include "output_plan.hpp"

#include <clvis/clvis.hpp>
#include <clvis/ray_io.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <iostream>

namespace clvis::cli {

namespace {

struct RaysArgs {
    SceneInput scene;
    DeviceOptions device;
    std::string rays, hits, counts;
    int max_hits = 0; ///< --max-hits (all hits only); 0: not given
    RayQueryKind query = RayQueryKind::Closest;
    std::size_t batch = std::size_t(1) << 20;
    bool brute = false, json = false, quiet = false;
};

/// The rays of `path`: read_rays' files, and also NumPy's default float64 as an (N, 8) .npy,
/// converted to float32 as the Python module's cast_rays does.
std::vector<RayRecord> read_rays_converted(const std::string& path)
{
    if (extension_of(path) != "npy") return read_rays(path);
    NpyArray a = read_npy(path);
    if (a.descr != "<f8") return read_rays(path); // float32, or refused there naming the dtype
    if (a.shape.size() != 2 || a.shape[1] != 8 || a.data.size() != a.shape[0] * 8 * sizeof(double))
        throw Error(Error::Kind::Io, path + ": rays must be an (N, 8) array of ox,oy,oz,tmin,dx,dy,dz,tmax");
    std::vector<RayRecord> rays(a.shape[0]);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        double d[8];
        std::memcpy(d, a.data.data() + i * sizeof d, sizeof d);
        rays[i] = RayRecord{float(d[0]), float(d[1]), float(d[2]), float(d[3]),
                            float(d[4]), float(d[5]), float(d[6]), float(d[7])};
    }
    return rays;
}

void rays_command(const RaysArgs& a)
{
    return_large_blocks();
    if (int ranks = mpi_world_size_from_environment(); ranks > 1)
        throw Error(Error::Kind::InvalidArgument, "--hits: clvis rays runs as " + std::to_string(ranks) +
                                                      " MPI processes (mpirun), which would all write '" + a.hits +
                                                      "'; run one process");
    const RayQueryKind kind = a.query;
    if (kind != RayQueryKind::All && (a.max_hits != 0 || !a.counts.empty()))
        throw Error(Error::Kind::InvalidArgument,
                    std::string(a.max_hits != 0 ? "--max-hits" : "--counts") + " needs --query all");
    if (kind == RayQueryKind::All && a.max_hits == 0)
        throw Error(Error::Kind::InvalidArgument, "--query all needs --max-hits K (1 to " +
                                                      std::to_string(ray_query_max_hits) + ")");
    OutputPlan plan;
    plan.add("--hits", a.hits, OutputKind::RayAnswers);
    if (!a.counts.empty()) plan.add("--counts", a.counts, OutputKind::RayAnswers);
    double load_ms = 0;
    SceneFile file = a.scene.load(&load_ms);
    if (file.scene.empty()) throw Error(Error::Kind::InvalidArgument, "the scene holds no triangles");
    std::vector<RayRecord> rays = read_rays_converted(a.rays);
    Device device = a.device.open();
    // The Renderer takes the scene over (issue 37: the mesh held once at the BVH build's peak).
    const std::size_t triangles = file.scene.triangle_count();
    Renderer renderer(device, std::move(file.scene));
    RayQueryOptions options;
    options.batch_rays = a.batch;
    options.brute = a.brute;
    auto t0 = std::chrono::steady_clock::now();
    RayQuery query(renderer, options);
    double build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    RayQueryStats stats;
    if (kind == RayQueryKind::Closest) {
        std::vector<HitRecord> hits(rays.size());
        stats = query.closest({rays.data(), rays.size()}, hits.data());
        write_hits(plan.temporary(a.hits), hits);
    } else if (kind == RayQueryKind::Any) {
        std::vector<std::uint8_t> flags(rays.size());
        stats = query.occluded({rays.data(), rays.size()}, flags.data());
        write_flags(plan.temporary(a.hits), flags);
    } else if (kind == RayQueryKind::All) {
        std::vector<HitRecord> hits(rays.size() * std::size_t(a.max_hits));
        std::vector<std::uint32_t> counts(a.counts.empty() ? 0 : rays.size());
        stats = query.all({rays.data(), rays.size()}, a.max_hits, hits.data(), a.counts.empty() ? nullptr : counts.data());
        write_hit_lists(plan.temporary(a.hits), hits, std::size_t(a.max_hits));
        if (!a.counts.empty()) write_counts(plan.temporary(a.counts), counts);
    } else {
        std::vector<std::uint32_t> counts(rays.size());
        stats = query.count({rays.data(), rays.size()}, counts.data());
        write_counts(plan.temporary(a.hits), counts);
    }
    std::vector<std::string> written = plan.commit();
    double mrays = stats.device_ms > 0 ? double(stats.rays) / (stats.device_ms * 1e3) : 0;
    if (!a.quiet) {
        char buf[256];
        std::snprintf(buf, sizeof buf, "clvis: %zu rays (%zu invalid) against %zu triangles on %s: %s in %.2f ms on the "
                                       "device (%.2f Mrays/s), %.2f ms with transfers, %zu batch(es)",
                      stats.rays, stats.invalid, triangles, device.info().name.c_str(),
                      to_string(kind), stats.device_ms, mrays, stats.wall_ms, stats.batches);
        std::cerr << buf << "\n";
        for (const std::string& f : written) std::cerr << "clvis: wrote " << f << "\n";
    }
    if (a.json) {
        nlohmann::json j{{"query", to_string(kind)},   {"rays", stats.rays},         {"invalid", stats.invalid},
                         {"triangles", triangles}, {"device", device.info().name},
                         {"load_ms", load_ms},         {"build_ms", build_ms},       {"device_ms", stats.device_ms},
                         {"wall_ms", stats.wall_ms},   {"batches", stats.batches},   {"mrays_per_s", mrays}};
        if (kind == RayQueryKind::All) j["max_hits"] = a.max_hits;
        std::cout << j.dump(2) << "\n";
    }
}

} // namespace

void add_rays_command(CLI::App& app)
{
    auto args = std::make_shared<RaysArgs>();
    auto* cmd = app.add_subcommand(
        "rays", "Answer a ray query for a file of rays: closest hits, occlusion, hit counts or all hits.\n"
                "Rays: .npy (N, 8) float32 (float64 is converted) ox,oy,oz,tmin,dx,dy,dz,tmax, or raw 32-byte "
                "records.\n"
                "Hits: .npy (structured t,id,u,v | uint8 | uint32; all hits (N, K) structured), or raw records as "
                ".bin or .raw.\n"
                "Example: clvis rays scenes/spot.obj --rays rays.npy --hits hits.npy --query closest");
    args->scene.add_to(*cmd);
    args->device.add_to(*cmd);
    cmd->add_option("--rays", args->rays, "the rays (.npy or raw records)")->required();
    cmd->add_option("--hits", args->hits, "where the answers go (.npy, or raw records as .bin or .raw)")->required();
    add_choice(*cmd, "--query", args->query,
               "closest, any (occlusion), count (half-open crossings) or all (the --max-hits nearest hits)");
    cmd->add_option("--max-hits", args->max_hits, "with --query all: hits kept per ray, nearest first by t then id")
        ->check(CLI::Range(1, ray_query_max_hits));
    cmd->add_option("--counts", args->counts,
                    "with --query all: the number of all hits of each ray, edges inclusive (uint32; .npy or raw)");
    cmd->add_option("--batch", args->batch, "rays per kernel launch at most")->check(CLI::Range(1, 1 << 28));
    cmd->add_flag("--brute", args->brute, "test every triangle instead of walking the BVH");
    cmd->add_flag("--json", args->json, "print one JSON object with the counts and timings on standard output");
    cmd->add_flag("--quiet,-q", args->quiet, "say nothing on standard error");
    add_verbose_flag(*cmd);
    cmd->callback([args] { rays_command(*args); });
}

} // namespace clvis::cli
