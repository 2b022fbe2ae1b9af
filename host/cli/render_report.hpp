// Parts of `clvis render --json` that say how a frame was made: its stage times and the raster
// and ray mappings that ran (RasterMapping::Auto and RayMapping::Auto resolved).
#pragma once

#include <clvis/clvis.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace clvis::cli {

/// Stage times by name; null when the queue gave none (FrameTiming::stages_measured).
nlohmann::json stages_json(const FrameTiming& t);

/// Sets j["raster_mapping"] to the mapping `renderer` ran, with "raster_mapping_source" (option,
/// forced, cache or measured) and, when measured, "raster_mapping_ms" {square, pixel}; without a
/// renderer (the raster path did not run), to `asked` alone.
void add_raster_mapping_json(nlohmann::json& j, Renderer* renderer, const std::string& asked);

/// The same for the ray path (Path::Ray): "ray_mapping", "ray_mapping_source", "ray_mapping_ms"
/// {packet, single}.
void add_ray_mapping_json(nlohmann::json& j, Renderer* renderer, const std::string& asked);

} // namespace clvis::cli
