// Reading scenes from files: Wavefront OBJ, PLY (ASCII and binary), STL (ASCII and binary),
// glTF 2.0 (.gltf, .glb), and the JSON scene file that names meshes, transforms and a camera.
// Every error names the file, the line, byte or JSON path, and what is wrong.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/camera_spec.hpp>
#include <clvis/scene.hpp>

#include <optional>
#include <string>
#include <vector>

namespace clvis {

/// Reads one mesh file; the format comes from the extension (.obj, .ply, .stl, .gltf, .glb), else
/// from the content. Throws Error(Io) naming the file (and line) on any malformed or unreadable input.
///  - Triangle ids follow CONVENTIONS.md: faces in file order, polygons fanned (v0, vk, vk+1),
///    degenerate faces kept. A file with no triangle at all (empty, points or lines only) is an
///    error: "contains no triangles".
///  - OBJ: every `v` becomes a vertex and every `f` (in any group) triangles; `l`, `p` and other
///    statements are skipped. Indices may be negative (relative); 0 or out of range is an error.
///    `normals` is filled when every face names normals and each position gets one normal.
///  - PLY: ascii and binary (either byte order); vertex x, y, z of any numeric type, faces from
///    the `vertex_indices` (or `vertex_index`) list; other elements are skipped.
///  - STL: ascii, or binary when the size is 84 + 50 n (even if it starts with "solid"). Facet i
///    gets vertices 3i, 3i+1, 3i+2: nothing is welded.
///  - Binary errors name the byte offset and the element; counts in headers are checked against
///    the file's size before anything is allocated.
///  - glTF 2.0: the items of load_gltf, flattened into one mesh in id order (each item's
///    positions transformed in double and rounded once, as Scene does).
///  - Attributes (MeshData::attributes, CONVENTIONS.md "Vertex attributes"), only when the file
///    has them: OBJ "uv" from `vt` through each corner's own index (corners without one NaN) and
///    "color" from `v x y z r g b` (alpha 1; vertices without a colour NaN); PLY "uv" (`u, v`,
///    `s, t` or `texture_u, texture_v`), "color" (`red, green, blue[, alpha]`, integers divided
///    by their type's maximum) and every other scalar vertex property but x, y, z, nx, ny, nz by
///    its name (characters other than letters, digits and '_' become '_'; two properties giving
///    one name are an error); glTF "uv", "uv1", "color" (TEXCOORD_0, TEXCOORD_1, COLOR_0; items
///    without one NaN). STL has none. Values are kept as the file stores them.
MeshData load_mesh(const std::string& path);

/// A glTF 2.0 file as CONVENTIONS.md's "Instances" reads it: the triangle primitives met in a
/// depth-first, pre-order walk of the default scene (scene 0 when none is named), root nodes,
/// children and primitives in file order, a node's own primitives before its children.
struct GltfScene {
    struct Item {
        std::size_t mesh = 0; ///< index into meshes
        Mat4 transform;       ///< product of the node transforms (matrix or T R S) along the path
        std::size_t node = 0; ///< the glTF node that holds it
    };
    /// One per (glTF mesh, primitive) that the walk meets, shared by every node using that mesh:
    /// POSITION as stored (float32), triangles in index order, strips and fans as the glTF
    /// specification orders them (strip: v_i, v_{i+1+i%2}, v_{i+2-i%2}; fan: v_{i+1}, v_{i+2},
    /// v_0), indexed or not, sparse accessors applied; attributes "uv", "uv1" and "color" from
    /// TEXCOORD_0, TEXCOORD_1 and COLOR_0 (normalised integers mapped as glTF says, RGB given
    /// alpha 1), per corner of these triangles.
    std::vector<MeshData> meshes;
    std::vector<Item> items;        ///< in id order
    /// What was skipped and why (points and lines, no POSITION, skins, morph targets), and one
    /// note listing the camera nodes of the scene ("cameras ignored ...: nodes[3] (cameras[0]
    /// \"Main\", perspective)"), which a mesh load does not use (load_views_file reads them as views).
    std::vector<std::string> notes;
    /// A camera node met in the walk (CONVENTIONS.md "Cameras from other tools"): which camera,
    /// at which world transform, and the camera's parameters as the file gives them.
    struct CameraNode {
        std::size_t node = 0;      ///< the glTF node that holds it
        int camera = 0;            ///< index into the file's cameras (checked: it exists)
        Mat4 transform;            ///< product of the node transforms along the path
        std::string name;          ///< the camera's name, may be empty
        bool orthographic = false; ///< else perspective
        double yfov = 0;           ///< perspective: vertical field of view, radians
        double ymag = 0;           ///< orthographic: half the view height
        double znear = 0, zfar = 0; ///< zfar 0: not given (perspective only)
    };
    std::vector<CameraNode> cameras; ///< in the order of the walk

    std::uint64_t triangle_count() const;
};

/// Reads a .gltf (buffers in files beside it or embedded as base64 data URIs) or a .glb. Throws
/// Error(Io) naming the file and what is wrong (with the glTF path, "meshes[2].primitives[0]"):
/// a glTF 1.0 file (asset.version, 1.0's layout, a GLB of version 1), JSON or GLB structure (the
/// GLB header's fault named), an accessor outside its buffer, an index past the vertices, a
/// non-finite position or transform, a node reached twice (nodes form disjoint trees), a required
/// extension that changes geometry (Draco, quantization, meshopt, GPU instancing), no triangle.
/// Images are never decoded. A build without tinygltf throws Error(Io) saying so.
GltfScene load_gltf(const std::string& path);

/// A scene file (JSON): meshes with optional transforms, an optional camera and image size.
///   { "meshes": [ {"file": "a.obj", "transform": [16 numbers, row by row]} ],
///     "camera": {"eye": [x,y,z], "target": [...], "up": [...], "fov": 45 | "ortho": h | true |
///                "focal_length": 35, "film_gate": [36, 24], "fit": "fill" | "overscan",
///                "near": n, "far": f},
///     "width": 1920, "height": 1080 }
/// A mesh with "instances" (instead of "transform") is a prototype: its instances are items at
/// its place in the list, in the order given (CONVENTIONS.md, "Instances").
/// Relative mesh paths are relative to the scene file's folder. "meshes" is required and not
/// empty. The camera takes every field of the command line's camera flags, under the same name
/// (camera_fields(): "film_gate" is --film-gate) and with the same meaning and defaults
/// (CameraSpec::resolve): no eye and target frames the scene, "ortho": true takes its height
/// from the scene's bounds, near and far default to the framing camera's depth range.
/// Unknown fields are errors. Every error is Error(Io) naming the file and the JSON path
/// ("meshes[1].transform: expected 16 numbers"). A build without nlohmann::json throws
/// Error(Io) saying so.
struct SceneFile {
    Scene scene;
    CameraSpec camera_spec;      ///< the camera as the file describes it (empty: none)
    std::optional<Camera> camera; ///< camera_spec resolved at the file's size (else 1920x1080)
    int width = 0, height = 0;   ///< 0 when the file does not say
};

SceneFile load_scene_file(const std::string& path);

/// Loads each path into one scene in order: mesh files, or a single scene file (.json), whose
/// camera and size are then dropped. A glTF file adds its items in order: a glTF mesh used by one
/// node as a mesh with its transform, one used by several as a prototype with an instance each. No path, or a .json among others, is Error(InvalidArgument).
Scene load_scene(const std::vector<std::string>& paths);

/// Appends a glTF scene's items to `scene` as load_scene does.
void add_gltf(Scene& scene, GltfScene gltf);

} // namespace clvis
