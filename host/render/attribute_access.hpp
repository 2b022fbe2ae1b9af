// The library's access to AttributeBuffers' members (include/clvis/attributes.hpp), shared by
// resolve.cpp (barycentrics, positions, normals) and resolve_corners.cpp (named attributes,
// object ids), and the renderer's cache of corner values on the device.
#pragma once

#include "render/renderer_impl.hpp"
#include "render/sample_scene.hpp"

#include <clvis/attributes.hpp>

#include <map>
#include <string>

namespace clvis {

struct AttributeAccess {
    using Named = AttributeBuffers::Named;
    static const Device& device(const AttributeBuffers& a) { return a.device_; }
    static std::shared_ptr<_cl_mem>& buffer(AttributeBuffers& a, Attribute which)
    {
        return a.buffers_[std::size_t(which)];
    }
    static void set(AttributeBuffers& a, const Device& device, int width, int height)
    {
        a.device_ = device;
        a.width_ = width;
        a.height_ = height;
    }
    static std::vector<Named>& named(AttributeBuffers& a) { return a.named_; }
    static std::shared_ptr<_cl_mem>& objects(AttributeBuffers& a) { return a.objects_; }
};

namespace detail {

/// What resolve_corners keeps on the device between calls, made on first use: the items' first
/// triangle ids, and per named attribute its corner values (each mesh and prototype once) and
/// where each item's start. The renderer's scene never changes its attributes or items
/// (Renderer::update moves vertices only), so it lives as long as the renderer.
struct CornerCache {
    struct Values {
        int components = 1;
        cl::Buffer values; ///< floats: the corner values of every mesh that has them
        cl::Buffer base;   ///< ulong per item: its first float in `values`, ~0 without
    };
    bool has_first = false;
    cl::Buffer first; ///< uint per item: Scene::Mesh::first_triangle
    std::map<std::string, Values> named;
};

/// Object ids and the named attributes of `request` into `target` (resolve() calls it after the
/// other attributes; `scene` is the sample scene it made, or null when it made none).
void resolve_corners(Renderer::Impl& r, const VisibilityBuffer& vis, const Camera& camera,
                     const AttributeRequest& request, AttributeBuffers& target, bool same_size,
                     const SampleScene* scene);

} // namespace detail
} // namespace clvis
