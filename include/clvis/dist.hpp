// MPI across processes and nodes (built only where MPI is found: clvis::dist). A communicator's
// ranks share many views by frames (each renders its own share of the cameras), or one frame by screen (sort-first: each renders a band of rows, gathered on rank 0)
// or by scene (sort-last: each holds a share of the triangles with their global ids, renders the
// whole image, and rank 0 keeps the element-wise minimum of the keys). Both give rank 0 the bits
// of one process rendering everything, since the key orders by depth, then by id.
#pragma once

#include <clvis/batch.hpp>
#include <clvis/render_options.hpp>
#include <clvis/renderer.hpp>
#include <clvis/scene.hpp>

#include <mpi.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace clvis::dist {

enum class Mode { Frames, Screen, Scene };
const char* to_string(Mode mode) noexcept;
/// "frames", "screen" or "scene"; throws Error(InvalidArgument) otherwise.
Mode mode_from_string(const std::string& name);

/// The triangles [first, last) of the whole scene that one rank holds.
struct Share {
    std::size_t first = 0, last = 0;
    std::size_t size() const { return last - first; }
};

/// Rank `rank` of `ranks`: an even, contiguous split of `count` items.
Share share_of(std::size_t count, int rank, int ranks);
/// The band of rows of a width x height image that rank `rank` of `ranks` renders (height 0 when
/// there are more ranks than rows).
Region rows_of(int width, int height, int rank, int ranks);
/// The triangles `share` of `scene` as a scene of their own: meshes outside it dropped, the
/// others cut, their vertices compacted, transforms kept. Its triangle k is `share.first + k` of
/// the whole scene.
Scene scene_part(const Scene& scene, Share share);

/// What rank 0 learns of a distributed frame (empty elsewhere).
struct Timing {
    std::vector<double> rank_ms; ///< each rank's own work (render and read-back), in rank order
    double composite_ms = 0;     ///< gathering or reducing the keys onto rank 0, after all finished
    std::size_t composite_bytes = 0; ///< key bytes sent to rank 0's composite, all ranks together
};

/// Frames: renders this rank's views, share_of(cameras.size(), rank, ranks), as one batch of
/// width x height (each view bit-identical to rendering it alone), then calls `on_view(v, buffer)`
/// for each, v being the view's index in `cameras` (to write its files or read its keys). Returns
/// this rank's share (empty when there are more ranks than views). Nothing is composited: rank
/// 0's timing has every rank's time for its batch and its on_view calls.
Share render_frames(MPI_Comm comm, Renderer& renderer, const std::vector<Camera>& cameras, int width, int height,
                    Path path, const std::function<void(int view, const VisibilityBuffer& keys)>& on_view,
                    Timing* timing = nullptr);

/// Screen: renders this rank's rows_of() band and gathers the keys on rank 0, which receives the
/// whole image (width * height keys, row 0 on top); other ranks receive an empty vector.
std::vector<std::uint64_t> render_screen(MPI_Comm comm, Renderer& renderer, const Camera& camera, int width,
                                         int height, Path path, Timing* timing = nullptr);

/// Scene: `renderer` holds the triangles from `id_base` on of the whole scene (scene_part of
/// share_of), or is null for an empty share. Renders the whole image, moves the ids to the whole
/// scene's, and reduces the keys by MPI_MIN onto rank 0, which receives them. With depth layers
/// (RenderOptions::layers, the largest of any rank's) each pixel's sorted lists are merged instead
/// (a user operation keeping the K smallest keys), K layer-major planes as a VisibilityBuffer's.
std::vector<std::uint64_t> render_scene(MPI_Comm comm, Renderer* renderer, std::uint32_t id_base,
                                        const Camera& camera, int width, int height, Path path,
                                        Timing* timing = nullptr);

} // namespace clvis::dist
