// The primary rays of a camera as an array (CONVENTIONS.md "Primary rays as arrays"): the rays
// the ray path casts, bit for bit, as ray-query records, so that closest-hit queries of them give
// the ray path's ids and depths (as t) sample for sample, and callers can perturb them. No OpenCL
// here: host-only code can include it.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/rays.hpp>

#include <string>
#include <vector>

namespace clvis {

/// The rays of every sample of a width x height image at `samples` per pixel (1, 2, 4, 8 or 16,
/// CONVENTIONS.md "Samples per pixel"), in the order of a visibility buffer's keys: record
/// (j * width + i) * samples + k is sample k of pixel (i, j), row 0 on top; together an array
/// (height, width, samples, 8) of float32. Each is the ray the ray path traces for that sample
/// (kernels/shared/camera.h's clvis_primary_ray on the float32 camera the kernels get, in the same
/// operations), with tmin = near and tmax = far in float32 and the direction unnormalised, so that
/// t is the view depth. Closest-hit RayQuery answers of these rays equal the ray path's render of
/// this camera at these samples, ids and depths bit for bit, under the watertight coverage rule
/// and no culling (a ray query knows no raster-rule coverage and no face culling). Throws
/// Error(InvalidArgument) for an invalid camera, a size below 1 or above 16384, or another
/// sample count.
std::vector<RayRecord> primary_rays(const Camera& camera, int width, int height, int samples = 1);

/// The same into caller storage of width * height * samples records.
void primary_rays(const Camera& camera, int width, int height, int samples, RayRecord* out);

} // namespace clvis
