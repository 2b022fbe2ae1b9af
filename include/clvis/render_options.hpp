// What a Renderer is asked for and what it reports: the path, options, stage and BVH timings.
// Plain types without OpenCL, shared by the Renderer, the paths behind it, the referee and the
// tools. Every RenderOptions field means the same on every path (Path::Raster, Path::Ray,
// Path::Brute): `cull` changes the answer, and every path and the referee apply it alike;
// `tile_size`, `raster_atomics`, `raster_mapping`, `ray_mapping` and `bvh` only tune one path's speed and never change an answer;
// `coverage` picks the ray paths' tie rule on shared edges (both answers are right, see Coverage).
// Every option enum has one names table (render_options.cpp): to_string, *_from_string and
// option_names<E>() read it, and the command line and the Python module take their names from it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace clvis {

enum class Path {
    Raster, ///< project, clip, bin into tiles, rasterize (64-bit atomic depth tests or tile ownership)
    Ray,    ///< one ray per pixel centre through a BVH
    Brute,  ///< one ray per pixel centre against every triangle (small scenes)
};

const char* to_string(Path path) noexcept;
/// "raster", "ray" or "brute"; throws Error(InvalidArgument) otherwise.
Path path_from_string(const std::string& name);

/// The names of every value of an option enum (Path, Cull, Coverage, BvhUpdate, RasterAtomics,
/// RasterMapping, RayMapping, shading.hpp's ShadeMode, camera.hpp's FilmFit and rays.hpp's
/// RayQueryKind) in declaration order: what to_string
/// gives and the enum's *_from_string accepts, for flags' checks and bindings.
template <class E>
const std::vector<std::string>& option_names();

/// The value of an option enum named `name`, as its *_from_string; throws
/// Error(InvalidArgument) otherwise, the message "<option>: expected one of <names>, got
/// '<name>'", <option> being the RenderOptions (ShadeOptions) field or "path", spelled as in Python.
template <class E>
E option_from_string(const std::string& name);

/// Face culling. A triangle (v0, v1, v2), its vertices in index order after its mesh's
/// transform, is front-facing when it appears counter-clockwise on screen (y up), that is when
/// the eye lies on the side its normal cross(v1 - v0, v2 - v0) points to (orthographic: the
/// normal points towards the camera, against the view direction). Only the positions as drawn
/// count: a mirroring transform (negative determinant) turns a mesh's front faces into back
/// faces, as in OpenGL; reverse the faces' winding to keep them. A triangle seen edge-on faces
/// neither way, and has no inside to draw.
enum class Cull {
    None,  ///< both sides visible (CONVENTIONS.md's default)
    Back,  ///< back faces dropped
    Front, ///< front faces dropped
};

const char* to_string(Cull cull) noexcept;
/// "none", "back" or "front"; throws Error(InvalidArgument) otherwise.
Cull cull_from_string(const std::string& name);

/// How the ray path decides that a primary ray's sample lies inside a triangle (Path::Ray and
/// Path::Brute; the raster path always applies its own rule).
enum class Coverage {
    /// The watertight ray/triangle test (Woop et al.), edges inclusive, depth = the ray's hit
    /// distance: buffers agree with the raster path's up to samples within float rounding of a
    /// shared edge (CONVENTIONS.md).
    Watertight,
    /// The raster path's own predicate for every candidate triangle of a primary ray: the same
    /// projection, clipping against near and the guard band, 16.16 snapping, edge functions with
    /// the top-left rule, culling and depth formula, so that ids and depths are bit-identical to
    /// Path::Raster's. Slower (a triangle set-up per candidate and packet).
    RasterRule,
};

const char* to_string(Coverage coverage) noexcept;
/// "watertight" or "raster-rule"; throws Error(InvalidArgument) otherwise.
Coverage coverage_from_string(const std::string& name);

/// How a BVH follows a mesh whose positions changed (Renderer::update).
enum class BvhUpdate { Refit, Rebuild };

const char* to_string(BvhUpdate update) noexcept;
/// "refit" or "rebuild"; throws Error(InvalidArgument) otherwise.
BvhUpdate bvh_update_from_string(const std::string& name);

struct BvhOptions {
    int max_leaf_size = 4; ///< triangles per leaf at most
    int sah_bins = 16;     ///< bins per axis of the binned SAH
    BvhUpdate update = BvhUpdate::Refit;
};

/// A rectangle of a full image's pixels. A render of a region fills a buffer of the region's size
/// with the bits the full render has at those pixels (both paths still compute in the full
/// image's raster space). Several devices and MPI ranks split images into regions.
struct Region {
    int x = 0, y = 0;          ///< the top-left pixel in the full image
    int width = 0, height = 0; ///< pixels; 0 x 0 means the whole image
    bool whole() const { return width == 0 && height == 0; }
};

/// How the raster path keeps the nearest key of a pixel. Both give the same keys, bit for bit.
enum class RasterAtomics {
    Auto, ///< 64-bit atomics where the device offers cl_khr_int64_base/extended_atomics, else Off;
          ///< on PoCL's CPU device a frame with at most one triangle per 16 keys is drawn as Off
    On,   ///< small triangles drawn at setup with 64-bit atomic min, the others binned and merged;
          ///< refused (Error(Device)) on a device without 64-bit atomics
    Off,  ///< tile ownership: every triangle binned, each pixel's nearest key kept in the private
          ///< memory of the one work-item that owns it and written once; no atomics on the keys
};

const char* to_string(RasterAtomics mode) noexcept;
/// "auto", "on" or "off"; throws Error(InvalidArgument) otherwise.
RasterAtomics raster_atomics_from_string(const std::string& name);

/// How the raster path's fine stage (kernels/raster_fine.cl) maps work onto a device. Both give
/// the same keys, bit for bit.
enum class RasterMapping {
    /// Square or Pixel, whichever ran faster on this device: measured on a short synthetic
    /// workload the first time a device, driver, kernel build, depth test and tile size are met,
    /// then read from the cache folder ($CLVIS_CACHE_DIR, else $XDG_CACHE_HOME/clvis, else
    /// ~/.cache/clvis). CLVIS_TUNE_CACHE=0 measures every time; CLVIS_TUNE_RASTER_MAPPING=square
    /// or pixel forces the choice. Renderer::raster_mapping() reports it.
    Auto,
    Square, ///< a work-item per square of up to 16x16 pixels of a tile, walking the tile's bin
            ///< alone on 8-pixel vector spans (suits CPU devices: PoCL vectorizes the spans)
    Pixel,  ///< a work-group per square of a tile, a work-item per pixel; the group walks the
            ///< tile's bin together, in batches of triangles copied into local memory (GPUs)
};

const char* to_string(RasterMapping mapping) noexcept;
/// "auto", "square" or "pixel"; throws Error(InvalidArgument) otherwise.
RasterMapping raster_mapping_from_string(const std::string& name);

/// The raster mapping a Renderer runs and where it came from (Renderer::raster_mapping()).
struct RasterMappingChoice {
    RasterMapping mapping = RasterMapping::Square; ///< Square or Pixel, never Auto
    /// "option" (RenderOptions named it), "forced" (Auto, CLVIS_TUNE_RASTER_MAPPING), "cache" (Auto,
    /// an earlier measurement) or "measured" (Auto, measured by this Renderer)
    std::string source = "option";
    /// Auto's measurement (the fastest frame of the tuning workload, host wall ms; -1 when not measured)
    double square_ms = -1, pixel_ms = -1;
};

/// How the ray path's primary rays (kernels/ray_trace*.cl) map onto a device. Both give the same
/// keys, bit for bit.
enum class RayMapping {
    /// Packet or Single, whichever ran faster on this device: measured on a short synthetic
    /// workload the first time a device, driver, kernel build and coverage mode are met, then read
    /// from the cache folder (as RasterMapping::Auto). CLVIS_TUNE_CACHE=0 measures every time;
    /// CLVIS_TUNE_RAY_MAPPING=packet or single forces the choice. Renderer::ray_mapping() reports it.
    Auto,
    Packet, ///< a work-item per packet of 4x4 pixels, one ray per lane of 16-wide vectors walking
            ///< the BVH together (suits CPU devices: PoCL runs the lanes as SIMD)
    Single, ///< a work-item per pixel, a work-group per tile of pixels, each ray walking alone (GPUs)
};

const char* to_string(RayMapping mapping) noexcept;
/// "auto", "packet" or "single"; throws Error(InvalidArgument) otherwise.
RayMapping ray_mapping_from_string(const std::string& name);

/// The ray mapping a Renderer's ray path runs and where it came from (Renderer::ray_mapping()).
struct RayMappingChoice {
    RayMapping mapping = RayMapping::Packet; ///< Packet or Single, never Auto
    /// "option", "forced" (CLVIS_TUNE_RAY_MAPPING), "cache" or "measured", as RasterMappingChoice
    std::string source = "option";
    /// Auto's measurement (the fastest frame of the tuning workload, host wall ms; -1 when not measured)
    double packet_ms = -1, single_ms = -1;
};

struct RenderOptions {
    int tile_size = 0;      ///< raster tile edge in pixels (a power of two); 0 picks the default
    /// Renderer::render(camera, width, height, path) renders only this part of the image, into a
    /// buffer of the region's size; the default is the whole image.
    Region region;
    Cull cull = Cull::None; ///< face culling, on every path (see Cull)
    RasterAtomics raster_atomics = RasterAtomics::Auto; ///< the raster path's depth test (see RasterAtomics)
    RasterMapping raster_mapping = RasterMapping::Auto; ///< the raster fine stage's mapping (see RasterMapping)
    RayMapping ray_mapping = RayMapping::Auto; ///< the ray path's primary-ray mapping (see RayMapping)
    BvhOptions bvh;         ///< the ray path's tree (Path::Ray; the brute path has none)
    Coverage coverage = Coverage::Watertight; ///< the ray paths' inside test (see Coverage)
    /// Samples per pixel: 1, 2, 4, 8 or 16, at the standard positions of CONVENTIONS.md
    /// "Samples per pixel" (kernels/shared/samples.h), on every path; a buffer then holds
    /// width x height x samples keys, the samples of a pixel adjacent. Anything else is refused
    /// (Error(InvalidArgument)).
    int samples = 1;
    /// Depth layers: 1 to 8 (CONVENTIONS.md "Depth layers"). With K > 1 every sample keeps the K
    /// nearest distinct triangles that cover it, sorted by key (depth bits, then id), missing
    /// layers background; layer 0 is the one-layer buffer bit for bit. Every path gives the same
    /// layers (in Coverage::RasterRule the ray paths' equal the raster path's bit for bit). The
    /// buffer holds K layers of width x height x samples keys, layer-major (VisibilityBuffer).
    /// Refused by name (Error(InvalidArgument)) with samples > 1 and by MPI's frames and screen
    /// modes; regions, instances, batches of views (VisibilityBatch with layers),
    /// MultiDeviceRenderer and MPI's scene mode (sorted lists merged) keep every layer.
    int layers = 1;
};

/// Checks RenderOptions::layers (1 to 8); throws Error(InvalidArgument) naming the value otherwise.
void check_layers(int layers);

/// log2 of a valid sample count (1, 2, 4, 8 or 16); throws Error(InvalidArgument) naming the
/// value otherwise.
int samples_log2(int samples);

struct StageTiming {
    std::string name; ///< e.g. "clear", "setup", "bin", "raster", "trace"
    double ms = 0;    ///< device time of the stage's kernels (profiling events)
};

struct FrameTiming {
    double frame_ms = 0;             ///< host wall time from the first enqueue to finish
    std::vector<StageTiming> stages; ///< in pipeline order; empty when !stages_measured
    /// Whether the stage times were measured. False when the Renderer enqueues on a wrapped
    /// queue made without CL_QUEUE_PROFILING_ENABLE: the stage times are then absent (not
    /// zero), and only frame_ms is known.
    bool stages_measured = false;
    /// The raster path's depth test in this frame, as RasterAtomics::Auto resolved it: On (64-bit
    /// atomics) or Off (tile ownership). Auto for the other paths.
    RasterAtomics raster_atomics = RasterAtomics::Auto;
};

struct BvhStats {
    double build_ms = 0;   ///< host build (or refit) time, upload excluded
    double upload_ms = 0;
    std::size_t nodes = 0, leaves = 0;
    int depth = 0;
    double sah_cost = 0;
    bool refitted = false; ///< the last update refitted rather than rebuilt
    /// A scene with instances (a two-level BVH): top-level entries (instances, and one for the
    /// plain meshes), the top level's last build time, and prototype trees built so far (moving an
    /// instance adds none).
    std::size_t instances = 0;
    double top_build_ms = 0;
    std::size_t prototype_builds = 0;
    std::uint64_t device_bytes = 0; ///< the BVH's device buffers (nodes, triangles, instances)
};

} // namespace clvis
