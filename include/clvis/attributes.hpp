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
#include <cstdint>
#include <memory>
#include <string>
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

/// The axes normals are given in (CONVENTIONS.md "Object ids"): world, or the camera's
/// (x = r, y = u, z = -f of "Camera frame").
enum class NormalSpace { World, Camera };
/// "world" or "camera".
const char* to_string(NormalSpace s) noexcept;
/// Throws Error(InvalidArgument) for any other name.
NormalSpace normal_space_from_string(const std::string& name);

/// A named face-varying attribute of a scene (MeshData::attributes) and its components.
struct AttributeInfo {
    std::string name;
    int components = 1;
};
/// Every named attribute the scene's items carry (a prototype's for its instances), in the order
/// first met item by item. Error(InvalidArgument) naming both meshes when two give one name
/// different component counts.
std::vector<AttributeInfo> scene_attributes(const Scene& scene);

/// Which attributes to resolve.
struct AttributeRequest {
    bool barycentrics = false;
    bool position = false;
    bool normal = false;
    bool smooth_normal = false;
    /// normal and smooth_normal in world or camera axes
    NormalSpace normal_space = NormalSpace::World;
    /// Named corner attributes ("uv", "color", any name of scene_attributes()): interpolated with
    /// the sample's barycentrics, NaN on the background and on items without them. A name no
    /// item carries is Error(InvalidArgument) listing those the scene has.
    std::vector<std::string> named;
    /// The object id (CONVENTIONS.md "Object ids"): the item index of each sample's triangle.
    bool object = false;

    bool has(Attribute a) const noexcept;
    bool any() const noexcept
    {
        return barycentrics || position || normal || smooth_normal || !named.empty() || object;
    }
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

    /// Named attributes: whether `name` was resolved, its components (Error when not resolved),
    /// its device buffer (components floats per pixel, adjacent) and blocking reads.
    bool has(const std::string& name) const;
    int components(const std::string& name) const;
    cl_mem buffer(const std::string& name) const;
    void read(const std::string& name, std::vector<float>& out) const;
    /// The names resolved, in the order asked.
    std::vector<std::string> names() const;

    /// Object ids: one uint32 per pixel, background 0xFFFFFFFF.
    bool has_objects() const { return bool(objects_); }
    cl_mem objects_buffer() const;
    void read_objects(std::vector<std::uint32_t>& out) const;

private:
    friend struct AttributeAccess;
    struct Named {
        std::string name;
        int components = 1;
        std::shared_ptr<struct _cl_mem> buffer;
    };
    const Named& named(const std::string& name) const;
    Device device_;
    std::array<std::shared_ptr<struct _cl_mem>, attribute_count> buffers_;
    std::vector<Named> named_;
    std::shared_ptr<struct _cl_mem> objects_;
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
