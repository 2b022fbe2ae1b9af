// The readers of views in other tools' formats (CONVENTIONS.md "Cameras from other tools"), from
// memory where the format is one file, behind load_views_file (host/scene/views_import.cpp).
// Each turns a camera into the CameraSpec that a clvis views file would hold and resolves it the
// way that file's reader does, so each view is bit for bit the same camera.
#pragma once

#include <clvis/views_file.hpp>

#include <optional>
#include <string>
#include <string_view>

namespace clvis::detail {

/// The image size a reader was given for files that lack one (--width, --height).
struct GivenSize {
    std::optional<int> width, height;
};

/// A JSON views file of any kind: NeRF's transforms.json ("frames"), glTF's JSON ("asset", no
/// "views"), else a clvis views file. Without nlohmann::json at build time: Error(Io).
ViewsFile parse_json_views(std::string_view text, const std::string& path, const GivenSize& size);
/// NeRF / instant-ngp transforms.json.
ViewsFile parse_nerf_views(std::string_view text, const std::string& path, const GivenSize& size);
/// The camera nodes of a glTF file (text or binary); buffers beside `path` read when `read_files`.
ViewsFile parse_gltf_views(std::string_view bytes, const std::string& path, const GivenSize& size, bool read_files);
/// A COLMAP text model from the texts of its cameras.txt and images.txt (named in errors).
ViewsFile parse_colmap_views(std::string_view cameras, const std::string& cameras_name, std::string_view images,
                             const std::string& images_name);

/// The shortest text that reads back as `v` (std::to_chars).
std::string shortest(double v);

} // namespace clvis::detail
