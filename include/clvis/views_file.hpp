// The views file of CONVENTIONS.md "Many views": a JSON list of cameras of one image size,
// {"width": W, "height": H, "views": [CAMERA, ...]}, each CAMERA with the camera fields of a
// scene file. Errors are Error(Io) naming the file and the JSON path ("views[3].eye: missing").
// The same reader takes the cameras of other tools (CONVENTIONS.md "Cameras from other tools"),
// told by content: NeRF / instant-ngp transforms.json, a COLMAP text model, a glTF file's cameras.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/scene.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace clvis {

/// Item transforms at one view (CONVENTIONS.md "Motion between views (flow)"): item index (a mesh
/// or an instance, in scene order) -> its transform at that view, replacing the scene's.
using ItemTransforms = std::map<std::size_t, Mat4>;

/// Where a ViewsFile's cameras came from.
enum class ViewsFormat {
    Clvis,  ///< {"width", "height", "views"}
    Nerf,   ///< NeRF / instant-ngp transforms.json (a JSON object with "frames")
    Colmap, ///< a COLMAP text model: a folder with cameras.txt and images.txt
    Gltf,   ///< the camera nodes of a glTF 2.0 file (.gltf, .glb)
};
/// "clvis", "nerf", "colmap", "gltf".
const char* to_string(ViewsFormat format) noexcept;

struct ViewsFile {
    int width = 0, height = 0;
    std::vector<Camera> views; ///< at least one
    /// One per view: a camera's "items" (each M affine and finite, checked when read); empty
    /// where the view keeps the scene's transforms.
    std::vector<ItemTransforms> items;
    std::string path; ///< the file, for messages (load_views_file sets it)
    ViewsFormat format = ViewsFormat::Clvis;

    /// Whether any view moves an item.
    bool moves() const;
};

/// Error(InvalidArgument) naming the file, the view and the item when a view's "items" names an
/// item `scene` does not have.
void check_view_items(const ViewsFile& views, const Scene& scene);

/// Reads the views at `path`, its format told by content: a folder (or its cameras.txt or
/// images.txt) is a COLMAP text model; a file starting with glTF's binary magic, or a JSON object
/// with "asset" and no "views" or "frames", is glTF; a JSON object with "frames" is NeRF's
/// transforms.json; else a clvis views file. `width` and `height` give the image size where the
/// file has none (glTF always; NeRF without "w", "h"); a size the file gives wins, as a clvis
/// views file's does. Every view renders bit-identical to the same camera written as a clvis
/// views file (views_file_text). Throws Error(Io) naming the file and the line or field: a
/// missing size (naming it), a distortion coefficient that is not zero, a COLMAP camera model
/// other than PINHOLE and SIMPLE_PINHOLE, cameras of different sizes, a pose whose 3x3 part is
/// not a rotation within 1e-6 (a glTF camera node whose world transform scales, too), no view.
ViewsFile load_views_file(const std::string& path, std::optional<int> width = std::nullopt,
                          std::optional<int> height = std::nullopt);

/// The clvis views file that reads back as exactly `views` (each camera's eye, target, up,
/// projection, near and far written as the shortest text that reads back to the same double).
std::string views_file_text(const ViewsFile& views);

/// `pattern` with "{view}" replaced by `view` zero-padded to the digits of `last` (the last
/// view's index); a pattern without "{view}" is returned unchanged.
std::string view_file_name(const std::string& pattern, int view, int last);

} // namespace clvis
