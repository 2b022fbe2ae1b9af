// clvis: visibility by rasterization and by ray casting on OpenCL. The umbrella header.
#pragma once

#include <clvis/config.hpp>

#include <clvis/attributes.hpp>
#include <clvis/batch.hpp>
#include <clvis/camera.hpp>
#include <clvis/camera_spec.hpp>
#include <clvis/device.hpp>
#include <clvis/error.hpp>
#include <clvis/flow.hpp>
#include <clvis/host_visibility.hpp>
#include <clvis/image.hpp>
#include <clvis/math.hpp>
#include <clvis/procedural.hpp>
#include <clvis/ray_io.hpp>
#include <clvis/ray_query.hpp>
#include <clvis/rays.hpp>
#include <clvis/referee.hpp>
#include <clvis/render_options.hpp>
#include <clvis/referee_attributes.hpp>
#include <clvis/referee_flow.hpp>
#include <clvis/renderer.hpp>
#include <clvis/scene.hpp>
#include <clvis/scene_io.hpp>
#include <clvis/shading.hpp>
#include <clvis/version.hpp>
#include <clvis/visibility.hpp>
#include <clvis/visible_set.hpp>
#if CLVIS_WITH_IMAGE_IO
#include <clvis/image_io.hpp>
#endif
