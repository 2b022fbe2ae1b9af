// clvis render --ao N --image FILE: the ambient-occlusion image of a visibility buffer (RayQuery's
// rays from each visible point), grey, black where the background shows.
#pragma once

#include <clvis/clvis.hpp>

namespace clvis::cli {

/// The ambient occlusion of `vis` as a grey image (white: open sky; black: background); says the
/// rays' count and speed on standard error unless `quiet`.
Image ao_image(Renderer& renderer, const VisibilityBuffer& vis, const Camera& camera, int rays, bool quiet);

} // namespace clvis::cli
