// Reading scenes from files: Wavefront OBJ, PLY (ASCII and binary), STL (ASCII and binary), and
// the JSON scene file that names meshes, transforms and a camera. Every error names the file,
// the line for text formats, and what is wrong.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/scene.hpp>

#include <optional>
#include <string>
#include <vector>

namespace clvis {

/// Reads one mesh file; the format comes from the extension (.obj, .ply, .stl), else from the
/// content. Throws Error(Io) naming the file (and line) on any malformed or unreadable input.
MeshData load_mesh(const std::string& path);

/// A scene file (JSON): meshes with optional transforms, an optional camera and image size.
///   { "meshes": [ {"file": "a.obj", "transform": [16 numbers, row by row]} ],
///     "camera": {"eye": [x,y,z], "target": [...], "up": [...], "fov": 45 | "ortho": h,
///                "near": n, "far": f},
///     "width": 1920, "height": 1080 }
/// Relative mesh paths are relative to the scene file's folder.
struct SceneFile {
    Scene scene;
    std::optional<Camera> camera;
    int width = 0, height = 0; ///< 0 when the file does not say
};

SceneFile load_scene_file(const std::string& path);

/// Loads each path into one scene in order: mesh files, or a single scene file (.json).
Scene load_scene(const std::vector<std::string>& paths);

} // namespace clvis
