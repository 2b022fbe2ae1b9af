// The mesh and scene parsers behind load_mesh and load_scene_file, from memory: the file
// loaders (host/scene/scene_io.cpp, scene_file.cpp) read a whole file and call these; the fuzz targets
// (tests/fuzz/) call them directly. `name` is the file name that every error message starts with.
#pragma once

#include <clvis/error.hpp>
#include <clvis/scene.hpp>
#include <clvis/scene_io.hpp>
#include <clvis/views_file.hpp>

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

namespace clvis::detail {

/// Wavefront OBJ: positions, faces fanned in file order, normals kept when every face names them
/// and each position is given one normal.
MeshData parse_obj(std::string_view text, const std::string& name);
/// PLY: ascii, binary_little_endian, binary_big_endian.
MeshData parse_ply(std::string_view bytes, const std::string& name);
/// STL: ascii or binary (binary when the size is exactly 84 + 50 n, or when the file does not
/// start with "solid"). Every facet gets three vertices of its own: nothing is welded.
MeshData parse_stl(std::string_view bytes, const std::string& name);

/// glTF 2.0, text (.gltf) or binary (.glb, told by its "glTF" magic). Buffers named by a uri are
/// read from the file's folder only when `read_files` (the fuzz targets pass false); data URIs
/// always work.
GltfScene parse_gltf(std::string_view bytes, const std::string& name, bool read_files);
/// The same walk for the camera reader (host/scene/views_gltf.cpp): a file without triangles is
/// no error, a camera node naming no camera is one, and out.cameras holds every camera node.
GltfScene parse_gltf_cameras(std::string_view bytes, const std::string& name, bool read_files);
/// The items of a glTF scene in id order as one mesh, positions transformed in double and rounded
/// once (the bits Scene gives the same items as meshes with transforms).
MeshData flatten_gltf(const GltfScene& gltf, const std::string& name);

enum class MeshFormat { Obj, Ply, Stl, Gltf, Unknown };
/// The format by the file's extension (case-insensitive), else Unknown.
MeshFormat format_from_extension(const std::string& path);
/// The format by the content: "ply" and "glTF" magic, STL ("solid" or the binary size rule), OBJ
/// keywords.
MeshFormat format_from_content(std::string_view bytes);
/// Dispatches to a parser by extension, else by content.
MeshData parse_mesh(std::string_view bytes, const std::string& path);

/// The JSON scene file; `load` reads each mesh (given the path already joined to the scene's
/// folder). Without nlohmann::json at build time this throws Error(Io) saying so.
SceneFile parse_scene_file(std::string_view text, const std::string& path,
                           const std::function<MeshData(const std::string&)>& load);

/// The JSON views file (include/clvis/views_file.hpp), its cameras read as a scene file's.
ViewsFile parse_views_file(std::string_view text, const std::string& path);

/// The whole content of a regular file; Error(Io) naming the file when it is missing, not a
/// regular file, or unreadable.
std::string read_file(const std::string& path);

/// Error(Io) with the message "<name>: <what>".
[[noreturn]] inline void fail(const std::string& name, const std::string& what)
{
    throw Error(Error::Kind::Io, name + ": " + what);
}
/// Error(Io) with the message "<name>:<line>: <what>" (text formats).
[[noreturn]] inline void fail_at_line(const std::string& name, std::size_t line, const std::string& what)
{
    throw Error(Error::Kind::Io, name + ":" + std::to_string(line) + ": " + what);
}

} // namespace clvis::detail
