// clvis render --distribute frames|screen|scene under mpirun: every rank opens its device and
// renders its part through clvis::dist; each rank writes its own views' --ids/--depth (frames) or
// rank 0 writes the frame's, and rank 0 says (or prints as --json) the frame, each rank's time
// and the composite's.
#include "render_dist.hpp"
#include "options.hpp"
#include "output_plan.hpp"

#include "bench_stats.hpp"

#include <clvis/dist.hpp>
#include <clvis/views_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

namespace clvis::cli {

namespace {

struct DistFrame {
    std::vector<std::uint64_t> keys; ///< on rank 0 (screen, scene)
    dist::Timing timing;
    double frame_ms = 0;             ///< rank 0's wall time of the whole distributed frame
};

/// What one rank holds for the frames: a renderer of the whole scene (screen) or of its share.
struct RankWork {
    std::unique_ptr<Renderer> renderer;
    std::uint32_t id_base = 0;
    std::size_t triangles = 0; ///< held by this rank
};

RankWork prepare(const SpreadRequest& r, Path path, const Device& device, int rank, int ranks)
{
    RankWork w;
    if (r.spread.distribute == "scene") {
        dist::Share share = dist::share_of(r.file->scene.triangle_count(), rank, ranks);
        Scene part = dist::scene_part(r.file->scene, share);
        r.file->scene = Scene(); // this rank holds only its share from here on
        w.id_base = std::uint32_t(share.first);
        w.triangles = share.size();
        if (share.size() > 0) w.renderer = std::make_unique<Renderer>(device, std::move(part), r.options);
    } else {
        w.triangles = r.file->scene.triangle_count();
        w.renderer = std::make_unique<Renderer>(device, r.file->scene, r.options);
    }
    if (w.renderer) w.renderer->prepare(path);
    return w;
}

/// This rank's files: its views' (frames) or, on rank 0, the frame's (screen, scene).
void plan_rank_files(OutputPlan& plan, const SpreadRequest& r, int rank, int ranks)
{
    dist::Share share{0, 0};
    if (r.spread.distribute == "frames") share = dist::share_of(r.cameras.size(), rank, ranks);
    else if (rank == 0) share = dist::share_of(1, 0, 1);
    int last = int(r.cameras.size()) - 1;
    for (std::size_t v = share.first; v < share.first + share.size(); ++v) {
        if (!r.ids.empty()) plan.add("--ids", view_file_name(r.ids, int(v), last), OutputKind::Ids);
        if (!r.depth.empty()) plan.add("--depth", view_file_name(r.depth, int(v), last), OutputKind::Depth);
    }
}

/// Writes one view's files under the plan's temporary names.
void write_buffers(const SpreadRequest& r, const OutputPlan& plan, const std::vector<std::uint64_t>& keys, int view,
                   int last)
{
    if (r.ids.empty() && r.depth.empty()) return;
#if CLVIS_WITH_IMAGE_IO
    // depth layers (--distribute scene): K layer-major planes
    int layers = int(keys.size() / (std::size_t(r.width) * std::size_t(r.height)));
    HostVisibility vis = split_keys(keys.data(), r.width, r.height, 1, layers > 1 ? layers : 1);
    if (!r.ids.empty()) write_ids(plan.temporary(view_file_name(r.ids, view, last)), vis);
    if (!r.depth.empty()) write_depth(plan.temporary(view_file_name(r.depth, view, last)), vis);
#else
    (void)plan, (void)keys, (void)view, (void)last;
    throw Error(Error::Kind::InvalidArgument, "--ids/--depth: this clvis was built without OpenImageIO");
#endif
}

/// Where a rank's files go and what went wrong writing them: an error is kept, not thrown, so
/// that every rank still reaches the frame's collectives and then the vote on the files.
struct RankFiles {
    OutputPlan plan;
    std::string error; ///< the first write error on this rank
    template <class F>
    void write(F&& f)
    {
        try {
            f();
        } catch (const std::exception& e) {
            if (error.empty()) error = e.what();
        }
    }
};

/// One distributed frame; with `files`, frames mode writes this rank's views' files (read back
/// in every frame, so that each frame's rank times hold the same work).
DistFrame one_frame(const SpreadRequest& r, Path path, RankWork& w, RankFiles* files)
{
    DistFrame f;
    MPI_Barrier(MPI_COMM_WORLD);
    auto t0 = std::chrono::steady_clock::now();
    const Camera& camera = r.cameras.front();
    if (r.spread.distribute == "frames") {
        int last = int(r.cameras.size()) - 1;
        std::vector<std::uint64_t> keys;
        dist::render_frames(MPI_COMM_WORLD, *w.renderer, r.cameras, r.width, r.height, path,
                            [&](int view, const VisibilityBuffer& vis) {
                                vis.read_keys(keys);
                                if (files) files->write([&] { write_buffers(r, files->plan, keys, view, last); });
                            },
                            &f.timing);
    } else if (r.spread.distribute == "scene") {
        f.keys = dist::render_scene(MPI_COMM_WORLD, w.renderer.get(), w.id_base, camera, r.width, r.height, path,
                                    &f.timing);
    } else {
        f.keys = dist::render_screen(MPI_COMM_WORLD, *w.renderer, camera, r.width, r.height, path, &f.timing);
    }
    f.frame_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return f;
}

void report(const SpreadRequest& r, Path path, const std::string& device, std::size_t triangles, int ranks,
            const std::vector<DistFrame>& frames)
{
    std::vector<double> samples;
    for (const auto& f : frames) samples.push_back(f.frame_ms);
    const DistFrame& best = *std::min_element(frames.begin(), frames.end(),
                                              [](const DistFrame& a, const DistFrame& b) { return a.frame_ms < b.frame_ms; });
    if (!r.quiet) {
        std::fprintf(stderr, "clvis: %s on %d ranks, %s path, %zu view(s): frame %.2f ms; composite %.2f ms (%zu bytes)\n",
                     r.spread.distribute.c_str(), ranks, to_string(path), r.cameras.size(), best.frame_ms,
                     best.timing.composite_ms, best.timing.composite_bytes);
        for (std::size_t k = 0; k < best.timing.rank_ms.size(); ++k)
            std::fprintf(stderr, "clvis:   rank %zu: %.2f ms\n", k, best.timing.rank_ms[k]);
    }
    if (!r.json) return;
    nlohmann::json j{{"path", to_string(path)},
                     {"distribute", r.spread.distribute},
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
                     {"views", r.cameras.size()},
                     {"camera", r.cameras.front().to_flags()}};
    std::cout << j.dump(2) << "\n";
}

/// All or none, over every rank: each rank writes its own files (frames: its views; screen and
/// scene: rank 0 the frame's) under temporary names; then the ranks vote (MPI_Allreduce), and
/// every rank renames its files only when no rank failed to write, else removes them. A rank that
/// fails while rendering aborts the job (MPI_Abort): it removes its own temporaries as it unwinds,
/// and since files are written only in the last frame, after the same work succeeded in the
/// warm-up (with --repeat), the others have rarely written any by then.
void run(const SpreadRequest& r, Path path)
{
    int rank = 0, ranks = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    RankFiles files;
    plan_rank_files(files.plan, r, rank, ranks);
    std::size_t triangles = r.file->scene.triangle_count();
    DeviceOptions device_options;
    device_options.spec = r.device_spec;
    Device device = device_options.open();
    RankWork w = prepare(r, path, device, rank, ranks);
    if (r.repeat > 0) one_frame(r, path, w, nullptr); // warm-up: first launches compile
    std::vector<DistFrame> frames;
    int count = std::max(r.repeat, 1);
    for (int i = 0; i < count; ++i) frames.push_back(one_frame(r, path, w, i == count - 1 ? &files : nullptr));
    if (rank == 0 && r.spread.distribute != "frames")
        files.write([&] { write_buffers(r, files.plan, frames.back().keys, 0, 0); });
    int failed = files.error.empty() ? 0 : 1, any_failed = 0;
    MPI_Allreduce(&failed, &any_failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (any_failed) {
        files.plan.discard();
        throw Error(Error::Kind::Io, (failed ? files.error : "another rank could not write its files") +
                                         "; no rank keeps its files");
    }
    for (const std::string& f : files.plan.commit())
        if (!r.quiet) std::fprintf(stderr, "clvis: rank %d wrote %s\n", rank, f.c_str());
    if (rank == 0) report(r, path, device.info().name, triangles, ranks, frames);
}

} // namespace

void render_distributed(const SpreadRequest& request, Path path)
{
    MPI_Init(nullptr, nullptr);
    try {
        run(request, path);
    } catch (const std::exception& e) {
        int rank = 0;
        MPI_Comm_rank(MPI_COMM_WORLD, &rank);
        std::cerr << "clvis: error on rank " << rank << ": " << e.what() << "\n";
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Finalize();
}

} // namespace clvis::cli
