// glTF 2.0 accessors into plain arrays for host/scene/scene_gltf.cpp: each element range is
// checked against its buffer view and buffer before a byte is read (counts and offsets are untrusted
// 64-bit numbers), components are copied with memcpy (no alignment assumed; glTF is little
// endian, as every host clvis runs on), then sparse substitutions are applied in order.
#ifdef CLVIS_HAVE_TINYGLTF

#include "scene/gltf_accessor.hpp"
#include "scene/scene_parsers.hpp"

#include <cstring>

namespace clvis::detail {

namespace {

std::size_t component_bytes(int type)
{
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
    }
}

const char* type_name(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "an unknown type";
    }
}

/// `count` elements of `elem` bytes, `stride` bytes apart, from byte `offset` of buffer view `view`.
struct Strided {
    const unsigned char* first = nullptr;
    std::size_t stride = 0;
};

Strided locate(const tinygltf::Model& model, int view, std::size_t offset, std::size_t count, std::size_t elem,
               std::size_t stride, const std::string& where, const std::string& name)
{
    if (view < 0 || std::size_t(view) >= model.bufferViews.size())
        fail(name, where + ": bufferView " + std::to_string(view) + " does not exist (the file has " +
                       std::to_string(model.bufferViews.size()) + ")");
    const tinygltf::BufferView& bv = model.bufferViews[std::size_t(view)];
    std::string at = "bufferViews[" + std::to_string(view) + "]";
    if (bv.buffer < 0 || std::size_t(bv.buffer) >= model.buffers.size())
        fail(name, at + ": buffer " + std::to_string(bv.buffer) + " does not exist");
    const std::vector<unsigned char>& data = model.buffers[std::size_t(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
        fail(name, at + ": bytes " + std::to_string(bv.byteOffset) + " + " + std::to_string(bv.byteLength) +
                       " lie outside buffer " + std::to_string(bv.buffer) + " (" + std::to_string(data.size()) +
                       " bytes)");
    if (stride == 0) stride = elem;
    if (stride < elem)
        fail(name, at + ": byteStride " + std::to_string(stride) + " is smaller than an element of " + where + " (" +
                       std::to_string(elem) + " bytes)");
    if (count > 0) {
        std::size_t length = bv.byteLength;
        if (offset > length || elem > length - offset || (count - 1) > (length - offset - elem) / stride)
            fail(name, where + ": " + std::to_string(count) + " elements of " + std::to_string(elem) +
                           " bytes from byte " + std::to_string(offset) + " do not fit in " + at + " (" +
                           std::to_string(length) + " bytes)");
    }
    return {data.data() + bv.byteOffset + offset, stride};
}

template <class T> T component(const unsigned char* p, int type)
{
    switch (type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return T(p[0]);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        std::uint16_t v;
        std::memcpy(&v, p, 2);
        return T(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return T(v);
    }
    default: { // FLOAT: the only other type the callers admit
        float v;
        std::memcpy(&v, p, 4);
        return T(v);
    }
    }
}

bool is_index_type(int type)
{
    return type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE || type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ||
           type == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
}

template <class T>
void apply_sparse(const tinygltf::Model& model, const tinygltf::Accessor& a, std::size_t comps, std::vector<T>& out,
                  const std::string& where, const std::string& name)
{
    const auto& sparse = a.sparse;
    if (sparse.count < 1 || std::size_t(sparse.count) > a.count)
        fail(name, where + ".sparse.count: " + std::to_string(sparse.count) + " is not within 1.." +
                       std::to_string(a.count));
    if (!is_index_type(sparse.indices.componentType))
        fail(name, where + ".sparse.indices.componentType: " + std::to_string(sparse.indices.componentType) +
                       " is not UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
    if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)
        fail(name, where + ".sparse: negative byteOffset");
    std::size_t count = std::size_t(sparse.count);
    std::size_t isize = component_bytes(sparse.indices.componentType);
    std::size_t csize = component_bytes(a.componentType);
    Strided ind = locate(model, sparse.indices.bufferView, std::size_t(sparse.indices.byteOffset), count, isize, isize,
                         where + ".sparse.indices", name);
    Strided val = locate(model, sparse.values.bufferView, std::size_t(sparse.values.byteOffset), count, comps * csize,
                         comps * csize, where + ".sparse.values", name);
    for (std::size_t k = 0; k < count; ++k) {
        std::uint32_t i = component<std::uint32_t>(ind.first + k * isize, sparse.indices.componentType);
        if (i >= a.count)
            fail(name, where + ".sparse.indices[" + std::to_string(k) + "]: " + std::to_string(i) +
                           " is past the accessor's " + std::to_string(a.count) + " elements");
        for (std::size_t c = 0; c < comps; ++c)
            out[std::size_t(i) * comps + c] = component<T>(val.first + k * comps * csize + c * csize, a.componentType);
    }
}

/// The component types an accessor may have: FLOAT; an index type; FLOAT or, normalized,
/// UNSIGNED_BYTE and UNSIGNED_SHORT (texture coordinates and colours).
enum class Admit { Float, Index, Normalized };

bool admits(const tinygltf::Accessor& a, Admit admit)
{
    switch (admit) {
    case Admit::Float: return a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
    case Admit::Index: return is_index_type(a.componentType);
    case Admit::Normalized:
        return a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
               (a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ||
                                 a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
    }
    return false;
}

const char* admitted(Admit admit)
{
    switch (admit) {
    case Admit::Float: return "FLOAT (KHR_mesh_quantization is not supported)";
    case Admit::Index: return "UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT";
    case Admit::Normalized: return "FLOAT, or UNSIGNED_BYTE or UNSIGNED_SHORT normalized";
    }
    return "";
}

/// The accessor's elements, `comps` components of type T each, after checking its type.
template <class T>
std::vector<T> read_elements(const tinygltf::Model& model, int index, int type, std::size_t comps, Admit admit,
                             const std::string& name)
{
    std::string where = "accessors[" + std::to_string(index) + "]";
    if (index < 0 || std::size_t(index) >= model.accessors.size())
        fail(name, where + " does not exist (the file has " + std::to_string(model.accessors.size()) + ")");
    const tinygltf::Accessor& a = model.accessors[std::size_t(index)];
    if (a.type != type)
        fail(name, where + ": type is " + type_name(a.type) + ", expected " + type_name(type));
    if (!admits(a, admit))
        fail(name, where + ": componentType " + std::to_string(a.componentType) +
                       (a.normalized ? " (normalized)" : "") + " is not " + admitted(admit));
    std::size_t elem = comps * component_bytes(a.componentType);
    std::vector<T> out;
    if (a.bufferView < 0) {
        if (a.count > CLVIS_GLTF_MAX_BUFFERLESS)
            fail(name, where + ": " + std::to_string(a.count) + " elements without a bufferView (at most " +
                           std::to_string(CLVIS_GLTF_MAX_BUFFERLESS) + ")");
        out.assign(a.count * comps, T(0));
    } else {
        std::size_t stride = model.bufferViews.size() > std::size_t(a.bufferView)
                                 ? model.bufferViews[std::size_t(a.bufferView)].byteStride
                                 : 0;
        Strided s = locate(model, a.bufferView, a.byteOffset, a.count, elem, stride, where, name);
        out.resize(a.count * comps);
        for (std::size_t e = 0; e < a.count; ++e)
            for (std::size_t c = 0; c < comps; ++c)
                out[e * comps + c] = component<T>(s.first + e * s.stride + c * (elem / comps), a.componentType);
    }
    if (a.sparse.isSparse) apply_sparse(model, a, comps, out, where, name);
    return out;
}

} // namespace

std::vector<float> read_positions(const tinygltf::Model& model, int accessor, const std::string& name)
{
    return read_elements<float>(model, accessor, TINYGLTF_TYPE_VEC3, 3, Admit::Float, name);
}

std::vector<std::uint32_t> read_indices(const tinygltf::Model& model, int accessor, const std::string& name)
{
    return read_elements<std::uint32_t>(model, accessor, TINYGLTF_TYPE_SCALAR, 1, Admit::Index, name);
}

std::vector<float> read_vertex_attribute(const tinygltf::Model& model, int accessor, bool color, int& components,
                                         const std::string& name)
{
    int type = TINYGLTF_TYPE_VEC2;
    if (color) { // VEC3 or VEC4: the accessor says which (read_elements names a missing one)
        type = TINYGLTF_TYPE_VEC4;
        if (accessor >= 0 && std::size_t(accessor) < model.accessors.size() &&
            model.accessors[std::size_t(accessor)].type == TINYGLTF_TYPE_VEC3)
            type = TINYGLTF_TYPE_VEC3;
    }
    components = type == TINYGLTF_TYPE_VEC2 ? 2 : type == TINYGLTF_TYPE_VEC3 ? 3 : 4;
    std::vector<float> out = read_elements<float>(model, accessor, type, std::size_t(components), Admit::Normalized, name);
    // Normalized integers as glTF 2.0 (section 3.11) maps them: c / 255, c / 65535.
    int ct = model.accessors[std::size_t(accessor)].componentType;
    double max = ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 255.0 : ct == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 65535.0 : 0;
    if (max > 0)
        for (float& v : out) v = float(double(v) / max);
    return out;
}

} // namespace clvis::detail

#endif // CLVIS_HAVE_TINYGLTF
