// What a Renderer is asked for and what it reports: the path, options, stage and BVH timings.
// Plain types without OpenCL, shared by the Renderer, the paths behind it and the tools.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace clvis {

enum class Path {
    Raster, ///< project, clip, bin into tiles, rasterize with 64-bit atomic depth tests
    Ray,    ///< one ray per pixel centre through a BVH
    Brute,  ///< one ray per pixel centre against every triangle (small scenes)
};

const char* to_string(Path path) noexcept;
/// "raster", "ray" or "brute"; throws Error(InvalidArgument) otherwise.
Path path_from_string(const std::string& name);

enum class Cull { None, Back, Front };

/// How a BVH follows a mesh whose positions changed (Renderer::update).
enum class BvhUpdate { Refit, Rebuild };

struct BvhOptions {
    int max_leaf_size = 4; ///< triangles per leaf at most
    int sah_bins = 16;     ///< bins per axis of the binned SAH
    BvhUpdate update = BvhUpdate::Refit;
};

struct RenderOptions {
    int tile_size = 0;      ///< raster tile edge in pixels (a power of two); 0 picks the default
    Cull cull = Cull::None; ///< face culling; front faces are counter-clockwise on screen
    BvhOptions bvh;
};

struct StageTiming {
    std::string name; ///< e.g. "clear", "setup", "bin", "raster", "trace"
    double ms = 0;    ///< device time of the stage's kernels (profiling events)
};

struct FrameTiming {
    double frame_ms = 0;             ///< host wall time from the first enqueue to finish
    std::vector<StageTiming> stages; ///< in pipeline order
};

struct BvhStats {
    double build_ms = 0;   ///< host build (or refit) time, upload excluded
    double upload_ms = 0;
    std::size_t nodes = 0, leaves = 0;
    int depth = 0;
    double sah_cost = 0;
    bool refitted = false; ///< the last update refitted rather than rebuilt
};

} // namespace clvis
