// Shading: a kernel over a visibility buffer turns ids and depths into a colour image. It knows
// nothing of how the buffer was made.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/image.hpp>
#include <clvis/renderer.hpp>
#include <clvis/visibility.hpp>

#include <string>

namespace clvis {

enum class ShadeMode {
    Lambert,   ///< facing ratio / Lambert with a directional light; smooth where normals exist
    Depth,     ///< view depth, near white to far black
    Ids,       ///< a false colour per triangle id
};

const char* to_string(ShadeMode mode) noexcept;
/// "lambert", "depth" or "ids" (render_options.cpp's table, as option_names<ShadeMode>()); throws
/// Error(InvalidArgument) otherwise, the message starting "mode: ".
ShadeMode shade_mode_from_string(const std::string& name);

struct ShadeOptions {
    ShadeMode mode = ShadeMode::Lambert;
    Vec3 light_direction{0.4, -0.8, -0.6}; ///< world space: the direction the light travels
};

/// Shades `vis` (made by `renderer` with `camera`) on the device.
Image shade(Renderer& renderer, const VisibilityBuffer& vis, const Camera& camera,
            const ShadeOptions& options = {});

} // namespace clvis
