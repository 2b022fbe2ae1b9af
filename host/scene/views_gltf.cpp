// The camera nodes of a glTF 2.0 file as views (CONVENTIONS.md "Cameras from other tools"): the
// walk of "Instances" (scene_gltf.cpp's, which keeps each camera node met with its world
// transform), each node posed by that transform (glTF cameras look down -z with y up, as clvis's
// frame), perspective yfov and znear, zfar or, absent, the far that a scene file's camera at this
// pose gets for the file's own triangles (the framing camera's far at the eye's distance);
// orthographic ymag is half the view height. aspectRatio and xmag are not read: the image size
// (--width, --height) decides the aspect, as for every clvis camera.
#include "scene/scene_parsers.hpp"
#include "scene/views_import.hpp"

#include <clvis/camera_spec.hpp>

#include <cmath>

namespace clvis::detail {

namespace {

constexpr double pi = 3.14159265358979323846;

/// The bounds of the file's triangles as `clvis render FILE.gltf` sees them (empty: none).
Bounds triangle_bounds(const GltfScene& g, const std::string& path)
{
    Bounds b;
    if (g.items.empty()) return b;
    MeshData m = flatten_gltf(g, path);
    for (std::size_t i = 0; i + 2 < m.positions.size(); i += 3)
        b.add({m.positions[i], m.positions[i + 1], m.positions[i + 2]});
    return b;
}

} // namespace

ViewsFile parse_gltf_views(std::string_view bytes, const std::string& path, const GivenSize& size, bool read_files)
{
    GltfScene g = parse_gltf_cameras(bytes, path, read_files);
    if (g.cameras.empty()) fail(path, "holds no camera node in its scene: no view");
    if (!size.width || !size.height)
        fail(path, std::string("glTF cameras give no image size: give ") +
                       (!size.width ? "--width" : "--height") + " (width=, height= in Python)");
    ViewsFile out;
    out.format = ViewsFormat::Gltf;
    out.width = *size.width;
    out.height = *size.height;
    bool need_bounds = false;
    for (const GltfScene::CameraNode& c : g.cameras) need_bounds |= !c.orthographic && !(c.zfar > 0);
    Bounds bounds = need_bounds ? triangle_bounds(g, path) : Bounds{};
    for (const GltfScene::CameraNode& c : g.cameras) {
        std::string node = "nodes[" + std::to_string(c.node) + "]";
        std::string cam = "cameras[" + std::to_string(c.camera) + "]." + (c.orthographic ? "orthographic" : "perspective");
        CameraSpec spec;
        spec.pose = c.transform;
        if (c.orthographic) {
            if (!(c.ymag > 0)) fail(path, cam + ".ymag: expected half the view height (> 0), got " + shortest(c.ymag));
            if (!(c.znear > 0))
                fail(path, cam + ".znear: " + shortest(c.znear) + ": clvis needs a near view depth > 0");
            spec.ortho = true;
            spec.ortho_height = 2 * c.ymag;
        } else {
            if (!(c.yfov > 0 && c.yfov < pi))
                fail(path, cam + ".yfov: expected a vertical field of view in radians in (0, pi), got " +
                               shortest(c.yfov));
            spec.fov = c.yfov * 180 / pi;
        }
        spec.near = c.znear;
        if (c.orthographic || c.zfar > 0) spec.far = c.zfar;
        try {
            out.views.push_back(spec.resolve(bounds, out.width, out.height, [&](const std::string& field) {
                if (field == "pose") return node + " (the world transform of " + cam.substr(0, cam.find('.')) + ")";
                if (field == "near") return cam + ".znear";
                if (field == "far") return cam + ".zfar";
                if (field == "fov") return cam + ".yfov";
                if (field == "ortho") return cam + ".ymag";
                return cam + "." + field;
            }));
        } catch (const Error& e) {
            fail(path, e.what());
        }
    }
    return out;
}

} // namespace clvis::detail
