// The referee of flow between views (CONVENTIONS.md "Motion between views (flow)"), in double
// precision on the host: from view A's ids, the cameras, view B's depths and the item transforms
// of each view, where each sample of A lands in B, whether that is valid and whether B sees
// something nearer there; each compared with a flow buffer (flow.x, flow.y, valid, occluded per
// pixel, as clvis::flow and `clvis render --flow` give it). No OpenCL.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/host_visibility.hpp>
#include <clvis/scene.hpp>
#include <clvis/views_file.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace clvis {

/// Tolerances of the judgement (CONVENTIONS.md): flow within flow_px; valid and occluded exact
/// except where the exact answer lies within a band of its threshold: depth within
/// threshold_relative of near or far, the projection within flow_px of the image's edge (or of a
/// pixel's edge, for the depth it is compared with), B's depth within occluded_band * depth of
/// the occlusion threshold depth * (1 - 1e-4).
struct FlowTolerance {
    double flow_px = 1e-3;
    double threshold_relative = 1e-3;
    double occluded_band = 1e-3 * 1e-4;
};

struct FlowReport {
    std::size_t samples = 0;         ///< pixels of A
    std::size_t foreground = 0;      ///< samples of A that see a triangle
    std::size_t valid = 0;           ///< samples the referee finds valid (ambiguous ones aside)
    std::size_t occluded = 0;        ///< of those, occluded beyond doubt
    std::size_t ambiguous = 0;       ///< samples whose valid or occluded answer was within a band
    std::size_t flow_errors = 0;     ///< flow off by more than flow_px, or NaN where valid, or not NaN where invalid
    std::size_t valid_errors = 0;    ///< valid mask wrong beyond the bands
    std::size_t occluded_errors = 0; ///< occluded mask wrong beyond the bands
    double max_flow_error = 0;       ///< px, over the samples both find valid
    std::string first_error;         ///< the first wrong sample, in words

    bool ok() const { return flow_errors == 0 && valid_errors == 0 && occluded_errors == 0; }
};

/// Judges `flow` (width * height * 4 floats of view A) against the flow recomputed in double from
/// `a`'s ids (view A, `camera_a`), `b`'s depths (view B, `camera_b`), and `scene`'s triangles placed
/// with `items_a` / `items_b` replacing the transforms of the items they name. Error(InvalidArgument)
/// for buffers of different sizes, more than one sample per pixel, a flow of the wrong size, or an
/// id or item `scene` does not have.
FlowReport judge_flow(const Scene& scene, const HostVisibility& a, const Camera& camera_a, const HostVisibility& b,
                      const Camera& camera_b, const std::vector<float>& flow, const ItemTransforms& items_a = {},
                      const ItemTransforms& items_b = {}, const FlowTolerance& tolerance = {});

} // namespace clvis
