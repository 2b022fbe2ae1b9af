// The tinygltf side of glTF loading: a checked GLB container, a bounded JSON depth, file access
// through our own callbacks, and each node's local transform. Used by host/scene/scene_gltf.cpp.
#pragma once

#include <clvis/math.hpp>

#include <tiny_gltf.h>

#include <string>
#include <string_view>

namespace clvis::detail {

/// JSON deeper than this is refused before tinygltf parses it (its extras parser recurses).
constexpr int CLVIS_GLTF_MAX_DEPTH = 64;

/// The parsed file: GLB when it starts with the "glTF" magic, else JSON text. Buffers named by a
/// uri are read beside `name` only when `read_files`; images are never read or decoded.
tinygltf::Model load_gltf_model(std::string_view bytes, const std::string& name, bool read_files);

/// A node's local transform: its column-major `matrix`, else T * R * S (unit quaternion x, y, z, w),
/// in double. `at` ("nodes[3]") starts every error message after the file name.
Mat4 gltf_node_transform(const tinygltf::Node& node, const std::string& at, const std::string& name);

} // namespace clvis::detail
