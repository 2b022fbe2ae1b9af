// The views file of CONVENTIONS.md "Many views": a JSON list of cameras of one image size,
// {"width": W, "height": H, "views": [CAMERA, ...]}, each CAMERA with the camera fields of a
// scene file. Errors are Error(Io) naming the file and the JSON path ("views[3].eye: missing").
#pragma once

#include <clvis/camera.hpp>

#include <string>
#include <vector>

namespace clvis {

struct ViewsFile {
    int width = 0, height = 0;
    std::vector<Camera> views; ///< at least one
};

ViewsFile load_views_file(const std::string& path);

/// `pattern` with "{view}" replaced by `view` zero-padded to the digits of `last` (the last
/// view's index); a pattern without "{view}" is returned unchanged.
std::string view_file_name(const std::string& pattern, int view, int last);

} // namespace clvis
