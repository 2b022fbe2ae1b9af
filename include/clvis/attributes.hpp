// Attributes resolved from a visibility buffer on the device (kernels/resolve.cl): per pixel the
// barycentrics of the visible triangle, its world position, its geometric normal and its smooth
// normal. Each comes from the pixel's id and its primary ray meeting the triangle's plane
// (kernels/shared/resolve.h), so both paths get them with one meaning; rendering asks for none
// of them, and a frame that does not resolve pays nothing for them.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/renderer.hpp>
#include <clvis/visibility.hpp>


#include <array>
#include <memory>
#include <vector>

namespace clvis {

enum class Attribute {
    Barycentrics, ///< u, v: P = (1 - u - v) v0 + u v1 + v v2 (CONVENTIONS.md); background 0, 0
    Position,     ///< x, y, z: world position of P; background NaN
    Normal,       ///< x, y, z: unit geometric normal, cross(v1 - v0, v2 - v0); background NaN
    SmoothNormal, ///< x, y, z: unit interpolated vertex normal, the geometric one where a mesh
                  ///< has none; background NaN
};
constexpr int attribute_count = 4;

/// Floats per pixel of an attribute: 2 for barycentrics, 3 for the others.
int channels(Attribute a) noexcept;
/// "barycentrics", "position", "normal" or "smooth_normal" (render_options.cpp's table, as
/// option_names<Attribute>(); Python's resolve() takes the same names).
const char* to_string(Attribute a) noexcept;
/// Throws Error(InvalidArgument) for any other name.
Attribute attribute_from_string(const std::string& name);

/// Which attributes to resolve.
struct AttributeRequest {
    bool barycentrics = false;
    bool position = false;
    bool normal = false;
    bool smooth_normal = false;

    bool has(Attribute a) const noexcept;
    bool any() const noexcept { return barycentrics || position || normal || smooth_normal; }
};

/// The resolved attributes of one visibility buffer, on the device: channels(a) floats per
/// pixel, pixels row by row with row 0 on top, channels adjacent.
class AttributeBuffers {
public:
    int width() const { return width_; }
    int height() const { return height_; }
    bool has(Attribute a) const { return bool(buffers_[std::size_t(a)]); }
    /// The device buffer of `a` (Error(InvalidArgument) when it was not resolved).
    cl_mem buffer(Attribute a) const;
    /// Blocking reads into storage the caller owns: a vector keeps its capacity; a pointer must
    /// address width() * height() * channels(a) floats.
    void read(Attribute a, float* out) const;
    void read(Attribute a, std::vector<float>& out) const;
    std::vector<float> read(Attribute a) const;

private:
    friend struct AttributeAccess;
    Device device_;
    std::array<std::shared_ptr<struct _cl_mem>, attribute_count> buffers_;
    int width_ = 0, height_ = 0;
};

/// Resolves `request` over `vis`, which `renderer` made with `camera`, into `target` (its
/// buffers reused when they fit, those not asked for released). Error(InvalidArgument) for an
/// empty buffer or one of another context.
void resolve(Renderer& renderer, const VisibilityBuffer& vis, const Camera& camera, const AttributeRequest& request,
             AttributeBuffers& target);
AttributeBuffers resolve(Renderer& renderer, const VisibilityBuffer& vis, const Camera& camera,
                         const AttributeRequest& request);

} // namespace clvis
