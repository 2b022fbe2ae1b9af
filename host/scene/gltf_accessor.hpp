// glTF 2.0 accessors read into plain arrays, every byte range checked against its buffer view and
// buffer first, sparse substitutions applied. Used by host/scene/scene_gltf.cpp (positions,
// indices, texture coordinates and colours); errors are Error(Io) "<file>: accessors[i]...: what".
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace clvis::detail {

/// An accessor without a buffer view is zeros (then its sparse values): one larger than this
/// many elements is refused rather than allocated from a count alone.
constexpr std::size_t CLVIS_GLTF_MAX_BUFFERLESS = std::size_t(1) << 24;

/// POSITION: FLOAT VEC3, 3 floats per element.
std::vector<float> read_positions(const tinygltf::Model& model, int accessor, const std::string& name);
/// Indices: UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT SCALAR.
std::vector<std::uint32_t> read_indices(const tinygltf::Model& model, int accessor, const std::string& name);
/// TEXCOORD_n (VEC2) or, when `color`, COLOR_n (VEC3 or VEC4): FLOAT, or UNSIGNED_BYTE /
/// UNSIGNED_SHORT normalized, divided by 255 / 65535 as glTF 2.0 says. `components` gets 2, 3 or 4.
std::vector<float> read_vertex_attribute(const tinygltf::Model& model, int accessor, bool color, int& components,
                                         const std::string& name);

} // namespace clvis::detail
