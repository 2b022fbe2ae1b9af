// The MPI modes of include/clvis/dist.hpp: splitting views, rows and triangles between ranks, and
// compositing their keys on rank 0 (MPI_Gatherv of row bands; MPI_Reduce with MPI_MIN on
// MPI_UINT64_T of whole images). Only the public C++ API and MPI's C API below.
#include <clvis/dist.hpp>

#include <clvis/error.hpp>
#include <clvis/host_visibility.hpp>

#include <algorithm>
#include <chrono>
#include <unordered_map>

namespace clvis::dist {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

void check_mpi(int code, const char* call)
{
    if (code == MPI_SUCCESS) return;
    char text[MPI_MAX_ERROR_STRING];
    int length = 0;
    MPI_Error_string(code, text, &length);
    throw Error(Error::Kind::Device, std::string(call) + " failed: " + std::string(text, std::size_t(length)));
}

int rank_in(MPI_Comm comm)
{
    int rank = 0;
    check_mpi(MPI_Comm_rank(comm, &rank), "MPI_Comm_rank");
    return rank;
}

int size_of(MPI_Comm comm)
{
    int size = 0;
    check_mpi(MPI_Comm_size(comm, &size), "MPI_Comm_size");
    return size;
}

/// Every rank's `ms` on rank 0, in rank order.
std::vector<double> gather_times(MPI_Comm comm, double ms)
{
    std::vector<double> all(std::size_t(size_of(comm)));
    check_mpi(MPI_Gather(&ms, 1, MPI_DOUBLE, all.data(), 1, MPI_DOUBLE, 0, comm), "MPI_Gather of times");
    return rank_in(comm) == 0 ? all : std::vector<double>{};
}

/// Every rank's `work_ms` (and rank 0's composite) into rank 0's `timing`, when asked for.
void report_times(MPI_Comm comm, Timing* timing, double work_ms, double composite_ms, std::size_t composite_bytes)
{
    std::vector<double> times = gather_times(comm, work_ms);
    if (!timing || rank_in(comm) != 0) return;
    timing->rank_ms = times;
    timing->composite_ms = composite_ms;
    timing->composite_bytes = composite_bytes;
}

void check_size(int width, int height)
{
    if (width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument, "image size must be positive, got " + std::to_string(width) + "x" +
                                                      std::to_string(height));
}

} // namespace

const char* to_string(Mode mode) noexcept
{
    switch (mode) {
    case Mode::Frames: return "frames";
    case Mode::Screen: return "screen";
    case Mode::Scene: return "scene";
    }
    return "?";
}

Mode mode_from_string(const std::string& name)
{
    if (name == "frames") return Mode::Frames;
    if (name == "screen") return Mode::Screen;
    if (name == "scene") return Mode::Scene;
    throw Error(Error::Kind::InvalidArgument, "distribution mode must be frames, screen or scene, got '" + name + "'");
}

Share share_of(std::size_t count, int rank, int ranks)
{
    if (ranks <= 0 || rank < 0 || rank >= ranks)
        throw Error(Error::Kind::InvalidArgument,
                    "rank " + std::to_string(rank) + " of " + std::to_string(ranks) + " does not exist");
    return {count * std::size_t(rank) / std::size_t(ranks), count * std::size_t(rank + 1) / std::size_t(ranks)};
}

Region rows_of(int width, int height, int rank, int ranks)
{
    Share rows = share_of(std::size_t(height), rank, ranks);
    return Region{0, int(rows.first), width, int(rows.size())};
}

Scene scene_part(const Scene& scene, Share share)
{
    if (share.first > share.last || share.last > scene.triangle_count())
        throw Error(Error::Kind::InvalidArgument, "triangles [" + std::to_string(share.first) + ", " +
                                                      std::to_string(share.last) + ") are not in a scene of " +
                                                      std::to_string(scene.triangle_count()));
    Scene part;
    std::size_t first_id = 0;
    for (const auto& mesh : scene.meshes()) {
        std::size_t count = mesh.data.triangle_count();
        std::size_t a = std::max(share.first, first_id), b = std::min(share.last, first_id + count);
        if (a < b) {
            MeshData cut;
            cut.name = mesh.data.name;
            std::unordered_map<std::uint32_t, std::uint32_t> kept; // old vertex -> new
            for (std::size_t i = 3 * (a - first_id); i < 3 * (b - first_id); ++i) {
                std::uint32_t v = mesh.data.indices[i];
                auto [it, fresh] = kept.emplace(v, std::uint32_t(kept.size()));
                if (fresh) {
                    for (int k = 0; k < 3; ++k) cut.positions.push_back(mesh.data.positions[3 * std::size_t(v) + k]);
                    if (!mesh.data.normals.empty())
                        for (int k = 0; k < 3; ++k) cut.normals.push_back(mesh.data.normals[3 * std::size_t(v) + k]);
                }
                cut.indices.push_back(it->second);
            }
            part.add_mesh(std::move(cut), mesh.transform);
        }
        first_id += count;
    }
    return part;
}

/// Depth layers: merges the sorted lists of K keys at `in` into those at `inout`, keeping the K
/// smallest distinct keys of each pixel (an MPI user operation; K from the datatype's size).
extern "C" void merge_layer_lists(void* in, void* inout, int* len, MPI_Datatype* type)
{
    int bytes = 0;
    MPI_Type_size(*type, &bytes);
    const std::size_t k = std::size_t(bytes) / 8;
    const auto* a = static_cast<const std::uint64_t*>(in);
    auto* b = static_cast<std::uint64_t*>(inout);
    std::uint64_t merged[8];
    for (int p = 0; p < *len; ++p, a += k, b += k) {
        std::size_t i = 0, j = 0, n = 0;
        while (n < k) {
            std::uint64_t x = i < k ? a[i] : background_key, y = j < k ? b[j] : background_key;
            std::uint64_t m = x < y ? x : y;
            i += x == m;
            j += y == m; // one copy of a key both hold
            merged[n++] = m;
        }
        std::copy_n(merged, k, b);
    }
}

/// Scene compositing of depth layers: `mine` (K layer-major planes) reduced into `whole` on rank 0
/// by merging each pixel's sorted lists (merge_layer_lists), pixels in one datatype of K keys.
static void reduce_layers(MPI_Comm comm, const std::vector<std::uint64_t>& mine, std::vector<std::uint64_t>& whole,
                   int layers)
{
    const std::size_t k = std::size_t(layers), pixels = mine.size() / k;
    std::vector<std::uint64_t> lists(mine.size()), merged(whole.empty() ? 0 : mine.size());
    for (std::size_t p = 0; p < pixels; ++p)
        for (std::size_t l = 0; l < k; ++l) lists[p * k + l] = mine[l * pixels + p];
    MPI_Datatype list_type;
    MPI_Op merge;
    check_mpi(MPI_Type_contiguous(layers, MPI_UINT64_T, &list_type), "MPI_Type_contiguous");
    check_mpi(MPI_Type_commit(&list_type), "MPI_Type_commit");
    check_mpi(MPI_Op_create(merge_layer_lists, 1, &merge), "MPI_Op_create");
    int status = MPI_Reduce(lists.data(), merged.data(), int(pixels), list_type, merge, 0, comm);
    MPI_Op_free(&merge);
    MPI_Type_free(&list_type);
    check_mpi(status, "MPI_Reduce (merge of sorted layers) of keys");
    for (std::size_t p = 0; p < merged.size() / k; ++p)
        for (std::size_t l = 0; l < k; ++l) whole[l * pixels + p] = merged[p * k + l];
}

/// MPI's frames and screen modes gather one key per pixel: depth layers (RenderOptions::layers) are refused.
static void check_one_layer(const Renderer* renderer)
{
    if (renderer && renderer->options().layers != 1)
        throw Error(Error::Kind::InvalidArgument, "MPI distribution composes one depth layer, the Renderer's options ask "
                                                  "for layers " +
                                                      std::to_string(renderer->options().layers));
}

Share render_frames(MPI_Comm comm, Renderer& renderer, const std::vector<Camera>& cameras, int width, int height,
                    Path path, const std::function<void(int view, const VisibilityBuffer& keys)>& on_view,
                    Timing* timing)
{
    check_one_layer(&renderer);
    check_size(width, height);
    int rank = rank_in(comm), ranks = size_of(comm);
    Share mine = share_of(cameras.size(), rank, ranks);
    auto t0 = Clock::now();
    if (mine.size() > 0) {
        std::vector<Camera> views(cameras.begin() + std::ptrdiff_t(mine.first), cameras.begin() + std::ptrdiff_t(mine.last));
        VisibilityBatch batch(renderer.device(), int(views.size()), width, height);
        render_views(renderer, views, path, batch);
        for (int v = 0; v < batch.views(); ++v) on_view(int(mine.first) + v, batch.view(v));
    }
    report_times(comm, timing, ms_since(t0), 0, 0);
    return mine;
}

std::vector<std::uint64_t> render_screen(MPI_Comm comm, Renderer& renderer, const Camera& camera, int width,
                                         int height, Path path, Timing* timing)
{
    check_one_layer(&renderer);
    check_size(width, height);
    int rank = rank_in(comm), ranks = size_of(comm);
    Region band = rows_of(width, height, rank, ranks);
    auto t0 = Clock::now();
    std::vector<std::uint64_t> mine;
    if (band.height > 0) {
        VisibilityBuffer target(renderer.device(), band.width, band.height);
        renderer.render(camera, width, height, band, path, target);
        mine = target.read_keys();
    }
    double work_ms = ms_since(t0);
    std::vector<int> counts(static_cast<std::size_t>(ranks)), offsets(static_cast<std::size_t>(ranks));
    for (int r = 0; r < ranks; ++r) {
        Region b = rows_of(width, height, r, ranks);
        counts[std::size_t(r)] = b.width * b.height;
        offsets[std::size_t(r)] = b.y * width;
    }
    std::vector<std::uint64_t> whole(rank == 0 ? std::size_t(width) * std::size_t(height) : 0);
    check_mpi(MPI_Barrier(comm), "MPI_Barrier");
    auto t1 = Clock::now();
    check_mpi(MPI_Gatherv(mine.data(), int(mine.size()), MPI_UINT64_T, whole.data(), counts.data(), offsets.data(),
                          MPI_UINT64_T, 0, comm),
              "MPI_Gatherv of row bands");
    report_times(comm, timing, work_ms, ms_since(t1), std::size_t(width) * std::size_t(height) * 8);
    return whole;
}

std::vector<std::uint64_t> render_scene(MPI_Comm comm, Renderer* renderer, std::uint32_t id_base,
                                        const Camera& camera, int width, int height, Path path, Timing* timing)
{
    check_size(width, height);
    int rank = rank_in(comm), ranks = size_of(comm);
    auto t0 = Clock::now();
    // Depth layers (RenderOptions::layers): every rank learns K, a rank without triangles too.
    int local_layers = renderer ? renderer->options().layers : 1, layers = 1;
    check_mpi(MPI_Allreduce(&local_layers, &layers, 1, MPI_INT, MPI_MAX, comm), "MPI_Allreduce of the layers");
    std::vector<std::uint64_t> mine(std::size_t(width) * std::size_t(height) * std::size_t(layers), background_key);
    if (renderer) {
        mine = renderer->render(camera, width, height, path).read_keys();
        // Local ids to the whole scene's: the same shift for every triangle keeps their order.
        for (auto& key : mine)
            if (key != background_key) key += id_base;
    }
    double work_ms = ms_since(t0);
    std::vector<std::uint64_t> whole(rank == 0 ? mine.size() : 0);
    check_mpi(MPI_Barrier(comm), "MPI_Barrier");
    auto t1 = Clock::now();
    if (layers == 1)
        check_mpi(MPI_Reduce(mine.data(), whole.data(), int(mine.size()), MPI_UINT64_T, MPI_MIN, 0, comm),
                  "MPI_Reduce (MPI_MIN) of keys");
    else
        reduce_layers(comm, mine, whole, layers);
    report_times(comm, timing, work_ms, ms_since(t1), mine.size() * 8 * std::size_t(ranks));
    return whole;
}

} // namespace clvis::dist
