// Per-vertex values to face-varying corners, attribute names, and attributes of meshes put end to
// end: the pieces scene_obj.cpp, scene_ply.cpp and scene_gltf.cpp share (corner_attributes.hpp).
#include "scene/corner_attributes.hpp"
#include "scene/scene_parsers.hpp"

#include <algorithm>
#include <cctype>
#include <iterator>
#include <limits>

namespace clvis::detail {

CornerAttribute corners_of(const VertexAttribute& a, const std::vector<std::uint32_t>& indices)
{
    CornerAttribute out;
    out.name = a.name;
    out.components = a.components;
    auto c = std::size_t(a.components);
    out.values.resize(indices.size() * c);
    float* dst = out.values.data();
    for (std::uint32_t v : indices) {
        const float* src = &a.values[std::size_t(v) * c];
        for (std::size_t k = 0; k < c; ++k) *dst++ = src[k];
    }
    return out;
}

std::string attribute_name(std::string_view name)
{
    std::string out(name);
    for (char& ch : out)
        if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '_')) ch = '_';
    return out;
}

std::vector<CornerAttribute> concatenate_attributes(const std::vector<const MeshData*>& meshes)
{
    std::vector<CornerAttribute> out;
    std::size_t corners = 0;
    for (const MeshData* m : meshes) {
        corners += m->indices.size();
        for (const CornerAttribute& a : m->attributes) {
            auto it = std::find_if(out.begin(), out.end(), [&](const CornerAttribute& o) { return o.name == a.name; });
            if (it == out.end()) {
                out.push_back({a.name, a.components, {}});
            } else {
                it->components = std::max(it->components, a.components);
            }
        }
    }
    if (out.empty()) return out;
    constexpr float nan = std::numeric_limits<float>::quiet_NaN();
    for (CornerAttribute& o : out) {
        auto c = std::size_t(o.components);
        o.values.assign(corners * c, nan);
        std::size_t first = 0; // first corner of the mesh
        for (const MeshData* m : meshes) {
            for (const CornerAttribute& a : m->attributes) {
                if (a.name != o.name) continue;
                auto ac = std::size_t(a.components);
                for (std::size_t i = 0; i < m->indices.size(); ++i)
                    std::copy_n(&a.values[i * ac], ac, &o.values[(first + i) * c]);
            }
            first += m->indices.size();
        }
    }
    return out;
}

namespace {

/// The index of the scalar property called `name`, or -1.
int find_scalar(const std::vector<PlyVertexProperty>& properties, std::string_view name)
{
    for (std::size_t k = 0; k < properties.size(); ++k)
        if (!properties[k].list && properties[k].name == name) return int(k);
    return -1;
}

} // namespace

PlyAttributePlan plan_ply_attributes(const std::vector<PlyVertexProperty>& properties, std::uint64_t vertices,
                                     const std::string& file)
{
    PlyAttributePlan plan;
    plan.slots.resize(properties.size());
    std::vector<std::string_view> given_by; // the property that named each attribute, for messages
    auto add = [&](std::string name, int components, std::string_view property) {
        for (std::size_t a = 0; a < plan.attributes.size(); ++a)
            if (plan.attributes[a].name == name)
                fail(file, "vertex property '" + std::string(property) + "' would be the attribute '" + name +
                               "', which vertex property '" + std::string(given_by[a]) + "' already gives");
        plan.attributes.push_back({std::move(name), components, {}});
        given_by.push_back(property);
        return int(plan.attributes.size()) - 1;
    };
    auto place = [&](int property, int attribute, int component) {
        PlyAttributePlan::Slot& s = plan.slots[std::size_t(property)];
        s.attribute = attribute;
        s.component = component;
        double max = properties[std::size_t(property)].integer_max;
        if (attribute >= 0 && plan.attributes[std::size_t(attribute)].name == "color" && max > 0) s.divisor = max;
    };
    static const char* const uv_pairs[][2] = {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}};
    for (const auto& pair : uv_pairs) {
        int u = find_scalar(properties, pair[0]), v = find_scalar(properties, pair[1]);
        if (u < 0 || v < 0) continue;
        int a = add("uv", 2, pair[0]);
        place(u, a, 0);
        place(v, a, 1);
        break;
    }
    int red = find_scalar(properties, "red"), green = find_scalar(properties, "green"),
        blue = find_scalar(properties, "blue");
    if (red >= 0 && green >= 0 && blue >= 0) {
        int a = add("color", 4, "red");
        place(red, a, 0);
        place(green, a, 1);
        place(blue, a, 2);
        int alpha = find_scalar(properties, "alpha");
        if (alpha >= 0) place(alpha, a, 3);
    }
    static const char* const geometry[] = {"x", "y", "z", "nx", "ny", "nz"};
    for (std::size_t k = 0; k < properties.size(); ++k) {
        const PlyVertexProperty& p = properties[k];
        if (p.list || plan.slots[k].attribute >= 0) continue;
        if (std::find_if(std::begin(geometry), std::end(geometry), [&](const char* g) { return p.name == g; }) !=
            std::end(geometry))
            continue;
        place(int(k), add(attribute_name(p.name), 1, p.name), 0);
    }
    for (VertexAttribute& a : plan.attributes)
        a.values.assign(std::size_t(vertices) * std::size_t(a.components), 1.0f); // alpha 1; the rest is read
    return plan;
}

} // namespace clvis::detail
