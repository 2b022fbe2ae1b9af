// Embree's answers for batches of arbitrary rays (the ray-query workloads of `clvis bench`),
// beside reference_embree.cpp which owns the scene. Internal to bench/: includes Embree.
#pragma once

#include "reference_embree.hpp"

#include <embree3/rtcore.h>

namespace clvis::bench {

/// Traces `rays` through `scene` as EmbreeReference::trace documents.
EmbreeRays trace_embree_rays(RTCScene scene, int threads, const RayRecord* rays, std::size_t n, bool occluded,
                             EmbreeMode mode, int repeats);

} // namespace clvis::bench
