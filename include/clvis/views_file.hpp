// The views file of CONVENTIONS.md "Many views": a JSON list of cameras of one image size,
// {"width": W, "height": H, "views": [CAMERA, ...]}, each CAMERA with the camera fields of a
// scene file. Errors are Error(Io) naming the file and the JSON path ("views[3].eye: missing").
#pragma once

#include <clvis/camera.hpp>
#include <clvis/scene.hpp>

#include <map>
#include <string>
#include <vector>

namespace clvis {

/// Item transforms at one view (CONVENTIONS.md "Motion between views (flow)"): item index (a mesh
/// or an instance, in scene order) -> its transform at that view, replacing the scene's.
using ItemTransforms = std::map<std::size_t, Mat4>;

struct ViewsFile {
    int width = 0, height = 0;
    std::vector<Camera> views; ///< at least one
    /// One per view: a camera's "items" (each M affine and finite, checked when read); empty
    /// where the view keeps the scene's transforms.
    std::vector<ItemTransforms> items;
    std::string path; ///< the file, for messages (load_views_file sets it)

    /// Whether any view moves an item.
    bool moves() const;
};

/// Error(InvalidArgument) naming the file, the view and the item when a view's "items" names an
/// item `scene` does not have.
void check_view_items(const ViewsFile& views, const Scene& scene);

ViewsFile load_views_file(const std::string& path);

/// `pattern` with "{view}" replaced by `view` zero-padded to the digits of `last` (the last
/// view's index); a pattern without "{view}" is returned unchanged.
std::string view_file_name(const std::string& pattern, int view, int last);

} // namespace clvis
