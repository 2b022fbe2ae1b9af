// clvis render --distribute screen|scene under mpirun: every rank opens its device and renders its
// part through clvis::dist; rank 0 writes --ids/--depth and says (or prints as --json) the frame,
// each rank's time and the composite's.
#include "render_dist.hpp"
#include "options.hpp"

#include "bench_stats.hpp"

#include <clvis/dist.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

namespace clvis::cli {

namespace {

struct DistFrame {
    std::vector<std::uint64_t> keys; ///< on rank 0
    dist::Timing timing;
    double frame_ms = 0;             ///< rank 0's wall time of the whole distributed frame
};

/// What one rank holds for the frames: a renderer of the whole scene (screen) or of its share.
struct RankWork {
    std::unique_ptr<Renderer> renderer;
    std::uint32_t id_base = 0;
    std::size_t triangles = 0; ///< held by this rank
};

RankWork prepare(DistRequest& r, const Device& device, int rank, int ranks)
{
    RankWork w;
    if (r.mode == "scene") {
        dist::Share share = dist::share_of(r.file.scene.triangle_count(), rank, ranks);
        Scene part = dist::scene_part(r.file.scene, share);
        r.file.scene = Scene(); // this rank holds only its share from here on
        w.id_base = std::uint32_t(share.first);
        w.triangles = share.size();
        if (share.size() > 0) w.renderer = std::make_unique<Renderer>(device, part, r.options);
    } else {
        w.triangles = r.file.scene.triangle_count();
        w.renderer = std::make_unique<Renderer>(device, r.file.scene, r.options);
    }
    if (w.renderer) w.renderer->prepare(r.path);
    return w;
}

DistFrame one_frame(const DistRequest& r, RankWork& w)
{
    DistFrame f;
    MPI_Barrier(MPI_COMM_WORLD);
    auto t0 = std::chrono::steady_clock::now();
    if (r.mode == "scene")
        f.keys = dist::render_scene(MPI_COMM_WORLD, w.renderer.get(), w.id_base, r.camera, r.width, r.height, r.path,
                                    &f.timing);
    else
        f.keys = dist::render_screen(MPI_COMM_WORLD, *w.renderer, r.camera, r.width, r.height, r.path, &f.timing);
    f.frame_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return f;
}

void write_buffers(const DistRequest& r, const std::vector<std::uint64_t>& keys)
{
    if (r.ids.empty() && r.depth.empty()) return;
#if CLVIS_WITH_IMAGE_IO
    HostVisibility vis = split_keys(keys.data(), r.width, r.height);
    if (!r.ids.empty()) write_ids(r.ids, vis);
    if (!r.depth.empty()) write_depth(r.depth, vis);
#else
    (void)keys;
    throw Error(Error::Kind::InvalidArgument, "--ids/--depth: this clvis was built without OpenImageIO");
#endif
}

void report(const DistRequest& r, const std::string& device, std::size_t triangles, int ranks,
            const std::vector<DistFrame>& frames)
{
    std::vector<double> samples;
    for (const auto& f : frames) samples.push_back(f.frame_ms);
    const DistFrame& best = *std::min_element(frames.begin(), frames.end(),
                                              [](const DistFrame& a, const DistFrame& b) { return a.frame_ms < b.frame_ms; });
    if (!r.quiet) {
        std::fprintf(stderr, "clvis: %s on %d ranks, %s path: frame %.2f ms; composite %.2f ms (%zu bytes)\n",
                     r.mode.c_str(), ranks, to_string(r.path), best.frame_ms, best.timing.composite_ms,
                     best.timing.composite_bytes);
        for (std::size_t k = 0; k < best.timing.rank_ms.size(); ++k)
            std::fprintf(stderr, "clvis:   rank %zu: %.2f ms\n", k, best.timing.rank_ms[k]);
    }
    if (!r.json) return;
    nlohmann::json j{{"path", to_string(r.path)},
                     {"distribute", r.mode},
                     {"ranks", ranks},
                     {"triangles", triangles},
                     {"width", r.width},
                     {"height", r.height},
                     {"device", device},
                     {"load_ms", r.load_ms},
                     {"frame_ms", {{"min", *std::min_element(samples.begin(), samples.end())},
                                   {"median", bench::median_of(samples)},
                                   {"samples", samples}}},
                     {"rank_ms", best.timing.rank_ms},
                     {"composite_ms", best.timing.composite_ms},
                     {"composite_bytes", best.timing.composite_bytes},
                     {"camera", r.camera.to_flags()}};
    std::cout << j.dump(2) << "\n";
}

void run(DistRequest& r)
{
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    std::size_t triangles = r.file.scene.triangle_count();
    DeviceOptions device_options;
    device_options.spec = r.device_spec;
    Device device = device_options.open();
    RankWork w = prepare(r, device, rank, ranks);
    if (r.repeat > 0) one_frame(r, w); // warm-up: first launches compile
    std::vector<DistFrame> frames;
    for (int i = 0; i < std::max(r.repeat, 1); ++i) frames.push_back(one_frame(r, w));
    if (rank != 0) return;
    write_buffers(r, frames.back().keys);
    report(r, device.info().name, triangles, ranks, frames);
}

} // namespace

void render_distributed(DistRequest request)
{
    MPI_Init(nullptr, nullptr);
    try {
        run(request);
    } catch (const std::exception& e) {
        int rank = 0;
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        std::cerr << "clvis: error on rank " << rank << ": " << e.what() << "\n";
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Finalize();
}

} // namespace clvis::cli
