// glTF 2.0 (.gltf, .glb) into a GltfScene: tinygltf parses the JSON, the GLB chunks and the
// buffers (files or base64 data URIs); this file walks the default scene's nodes and turns each
// triangle primitive into ids exactly as CONVENTIONS.md's "Instances" section says, with its
// TEXCOORD_0, TEXCOORD_1 and COLOR_0 as the attributes "uv", "uv1" and "color" (CONVENTIONS.md
// "Vertex attributes": per corner, in the triangles' order, once per shared mesh). Called by
// load_mesh / load_scene / load_gltf (host/scene/scene_io.cpp) and by the fuzz target fuzz_gltf.
//
// Why tinygltf and not assimp, compared on the .gltf/.glb files of Debian's assimp-testmodels
// (/usr/share/assimp/models/glTF2):
//  - ids: tinygltf hands over the file's own nodes, accessors and primitive modes, so the walk,
//    strips, fans, sparse accessors and index order below are ours and follow the spec to the
//    letter; assimp converts them into aiMeshes of its own faces (strips and fans triangulated by
//    its code, not checked against the spec's order here) and drops what it judges bad (a face
//    of IndexOutOfRange dropped; AllIndicesOutOfRange refused as "no faces").
//  - loads: assimp refused files (wrongTypes/bad{Extension,Number,Object,String,Uint},
//    issue_3269) for material, texture or name fields that play no part in visibility; tinygltf
//    refused only files whose buffers are missing (MissingBin, sceneWrongType) and the Draco file,
//    and of what it parses the checks below refuse the malformed with a message naming the fault.
//  - speed: of the same order for both.
//  - surface: one header, no post-processing, and its file access goes through callbacks we own
//    (no path expansion, images never decoded), which the fuzz target compiles instrumented.
#include "scene/corner_attributes.hpp"
#include "scene/instance_transform.hpp"
#include "scene/scene_parsers.hpp"

#include <clvis/scene_io.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>

#ifdef CLVIS_HAVE_TINYGLTF
#include "scene/gltf_accessor.hpp"
#include "scene/gltf_model.hpp"
#endif

namespace clvis {

std::uint64_t GltfScene::triangle_count() const
{
    std::uint64_t n = 0;
    for (const Item& item : items) n += meshes[item.mesh].triangle_count();
    return n;
}

namespace detail {

MeshData flatten_gltf(const GltfScene& gltf, const std::string& name)
{
    std::uint64_t triangles = gltf.triangle_count(), vertices = 0;
    for (const GltfScene::Item& item : gltf.items) vertices += gltf.meshes[item.mesh].vertex_count();
    if (triangles > max_triangles || vertices > 0xFFFFFFFFull)
        throw Error(Error::Kind::Limit, name + ": the scene expands to " + std::to_string(triangles) +
                                            " triangles and " + std::to_string(vertices) +
                                            " vertices, more than 32-bit ids and indices allow");
    MeshData out;
    out.name = name;
    out.positions.reserve(std::size_t(vertices) * 3);
    out.indices.reserve(std::size_t(triangles) * 3);
    std::vector<const MeshData*> placed; // the meshes in item order, for their attributes
    for (const GltfScene::Item& item : gltf.items) {
        const MeshData& m = gltf.meshes[item.mesh];
        auto first = std::uint32_t(out.vertex_count());
        std::size_t at = out.positions.size();
        out.positions.resize(at + m.positions.size());
        detail::transform_positions(item.transform, m.positions.data(), m.vertex_count(), &out.positions[at]);
        for (std::size_t i = at; i < out.positions.size(); ++i)
            if (!std::isfinite(out.positions[i]))
                fail(name, "nodes[" + std::to_string(item.node) + "]: a transformed vertex overflows float32");
        for (std::uint32_t index : m.indices) out.indices.push_back(first + index);
        placed.push_back(&m);
    }
    out.attributes = concatenate_attributes(placed);
    return out;
}

#ifdef CLVIS_HAVE_TINYGLTF

namespace {

const char* mode_name(int mode)
{
    static const char* names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
    return mode >= 0 && mode < 4 ? names[mode] : "unknown";
}

/// The triangles of `order` (vertex numbers in index order) for a primitive mode, as the glTF 2.0
/// specification (section 3.7.2.1) orders them.
std::vector<std::uint32_t> assemble(const std::vector<std::uint32_t>& order, int mode, const std::string& where,
                                    const std::string& name)
{
    std::size_t n = order.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        if (n % 3)
            fail(name, where + ": " + std::to_string(n) + " vertices for TRIANGLES, not a multiple of 3");
        return order;
    }
    std::vector<std::uint32_t> out;
    if (n < 3) return out;
    out.reserve((n - 2) * 3);
    for (std::size_t i = 0; i + 2 < n; ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) // p_i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}}
            out.insert(out.end(), {order[i], order[i + 1 + i % 2], order[i + 2 - i % 2]});
        else // TRIANGLE_FAN: p_i = {v_{i+1}, v_{i+2}, v_0}
            out.insert(out.end(), {order[i + 1], order[i + 2], order[0]});
    }
    return out;
}

class Walker {
public:
    /// `need_triangles`: a file without triangles is an error (false: the camera reader's walk).
    Walker(const tinygltf::Model& model, const std::string& name, bool need_triangles = true)
        : model_(model), name_(name), need_triangles_(need_triangles)
    {
    }

    GltfScene run()
    {
        if (model_.scenes.empty()) fail(name_, "contains no scene, so nothing to draw");
        int scene = model_.defaultScene < 0 ? 0 : model_.defaultScene;
        if (std::size_t(scene) >= model_.scenes.size())
            fail(name_, "scene: " + std::to_string(scene) + " does not exist (the file has " +
                            std::to_string(model_.scenes.size()) + ")");
        std::vector<char> seen(model_.nodes.size(), 0);
        std::vector<std::pair<int, Mat4>> stack; // depth-first, pre-order: children pushed reversed
        const std::vector<int>& roots = model_.scenes[std::size_t(scene)].nodes;
        for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.emplace_back(*it, Mat4::identity());
        while (!stack.empty()) {
            auto [node, parent] = stack.back();
            stack.pop_back();
            std::string at = "nodes[" + std::to_string(node) + "]";
            if (node < 0 || std::size_t(node) >= model_.nodes.size())
                fail(name_, at + " does not exist (the file has " + std::to_string(model_.nodes.size()) + ")");
            if (seen[std::size_t(node)]++)
                fail(name_, at + " is reached twice (glTF nodes form disjoint trees)");
            const tinygltf::Node& n = model_.nodes[std::size_t(node)];
            Mat4 world = parent * gltf_node_transform(n, at, name_);
            for (double v : world.m)
                if (!std::isfinite(v)) fail(name_, at + ": the transform along the path overflows");
            if (n.skin >= 0) note(at + ": skin ignored, the mesh is drawn in its bind pose");
            if (n.mesh >= 0) items(std::size_t(node), n.mesh, world);
            if (n.camera >= 0) camera(at, n.camera, std::size_t(node), world);
            for (auto it = n.children.rbegin(); it != n.children.rend(); ++it) stack.emplace_back(*it, world);
        }
        if (out_.items.empty() && need_triangles_) {
            std::string why;
            for (const std::string& s : out_.notes) why += (why.empty() ? " (" : "; ") + s;
            fail(name_, "contains no triangles" + (why.empty() ? std::string() : why + ")"));
        }
        if (!cameras_.empty()) note("cameras ignored (clvis places its own camera): " + cameras_);
        return std::move(out_);
    }

private:
    void note(const std::string& s) { out_.notes.push_back(s); }

    /// "nodes[3] (cameras[0] \"Main\", perspective)", listed in one note at the end of the walk.
    /// The node is kept in out_.cameras with the camera's parameters when the camera exists.
    void camera(const std::string& at, int camera, std::size_t node, const Mat4& world)
    {
        std::string what = "cameras[" + std::to_string(camera) + "]";
        if (std::size_t(camera) < model_.cameras.size()) {
            const tinygltf::Camera& c = model_.cameras[std::size_t(camera)];
            if (!c.name.empty()) what += " \"" + c.name + "\"";
            if (!c.type.empty()) what += ", " + c.type;
            GltfScene::CameraNode k;
            k.node = node;
            k.camera = camera;
            k.transform = world;
            k.name = c.name;
            k.orthographic = c.type == "orthographic";
            k.yfov = c.perspective.yfov;
            k.ymag = c.orthographic.ymag;
            k.znear = k.orthographic ? c.orthographic.znear : c.perspective.znear;
            k.zfar = k.orthographic ? c.orthographic.zfar : c.perspective.zfar;
            if (k.orthographic || c.type == "perspective") out_.cameras.push_back(k);
            else if (!need_triangles_)
                fail(name_, "cameras[" + std::to_string(camera) + "].type: '" + c.type +
                                "' is neither perspective nor orthographic");
        } else {
            if (!need_triangles_) fail(name_, at + ".camera: " + std::to_string(camera) + " does not exist");
            what += " (does not exist)";
        }
        cameras_ += (cameras_.empty() ? "" : ", ") + at + " (" + what + ")";
    }

    void items(std::size_t node, int mesh, const Mat4& world)
    {
        if (std::size_t(mesh) >= model_.meshes.size())
            fail(name_, "nodes[" + std::to_string(node) + "].mesh: " + std::to_string(mesh) + " does not exist");
        const auto& primitives = model_.meshes[std::size_t(mesh)].primitives;
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            auto key = std::make_pair(mesh, p);
            auto found = prototypes_.find(key);
            if (found == prototypes_.end())
                found = prototypes_.emplace(key, primitive(mesh, p, primitives[p])).first;
            if (!found->second) continue;
            const MeshData& m = out_.meshes[*found->second];
            triangles_ += m.triangle_count();
            if (triangles_ > max_triangles)
                throw Error(Error::Kind::Limit, name_ + ": the scene holds more triangles than 32-bit ids allow (" +
                                                    std::to_string(max_triangles) + ")");
            out_.items.push_back({*found->second, world, node});
        }
    }

    /// The mesh of one primitive, or nothing (with a note) for a primitive without triangles.
    std::optional<std::size_t> primitive(int mesh, std::size_t p, const tinygltf::Primitive& prim)
    {
        std::string where = "meshes[" + std::to_string(mesh) + "].primitives[" + std::to_string(p) + "]";
        if (prim.mode >= 0 && prim.mode < TINYGLTF_MODE_TRIANGLES) {
            note(where + ": mode " + mode_name(prim.mode) + " skipped (no triangles)");
            return std::nullopt;
        }
        if (prim.mode > TINYGLTF_MODE_TRIANGLE_FAN || prim.mode < 0)
            fail(name_, where + ".mode: " + std::to_string(prim.mode) + " is not a glTF primitive mode");
        auto position = prim.attributes.find("POSITION");
        if (position == prim.attributes.end()) {
            note(where + ": no POSITION, skipped");
            return std::nullopt;
        }
        MeshData m;
        m.name = name_ + " " + where;
        m.positions = read_positions(model_, position->second, name_);
        for (std::size_t i = 0; i < m.positions.size(); ++i)
            if (!std::isfinite(m.positions[i]))
                fail(name_, where + ": POSITION of vertex " + std::to_string(i / 3) + " is not finite");
        std::size_t vertices = m.vertex_count();
        if (vertices > 0xFFFFFFFFull) fail(name_, where + ": more vertices than 32-bit indices allow");
        std::vector<std::uint32_t> order;
        if (prim.indices >= 0) {
            order = read_indices(model_, prim.indices, name_);
            for (std::size_t k = 0; k < order.size(); ++k)
                if (order[k] >= vertices)
                    fail(name_, where + ": index " + std::to_string(k) + " is " + std::to_string(order[k]) +
                                    ", past the " + std::to_string(vertices) + " vertices of POSITION");
        } else {
            order.resize(vertices);
            for (std::size_t v = 0; v < vertices; ++v) order[v] = std::uint32_t(v);
        }
        m.indices = assemble(order, prim.mode, where, name_);
        if (!prim.targets.empty()) note(where + ": morph targets ignored, the base POSITION is drawn");
        if (m.indices.empty()) {
            note(where + ": fewer than 3 vertices, no triangle");
            return std::nullopt;
        }
        attributes(prim, m, where);
        out_.meshes.push_back(std::move(m));
        return out_.meshes.size() - 1;
    }

    /// TEXCOORD_0, TEXCOORD_1 and COLOR_0 per corner of m's triangles (COLOR_0 as RGB gets alpha 1).
    void attributes(const tinygltf::Primitive& prim, MeshData& m, const std::string& where)
    {
        static const struct { const char* gltf; const char* name; bool color; } known[] = {
            {"TEXCOORD_0", "uv", false}, {"TEXCOORD_1", "uv1", false}, {"COLOR_0", "color", true}};
        for (const auto& k : known) {
            auto it = prim.attributes.find(k.gltf);
            if (it == prim.attributes.end()) continue;
            int components = 0;
            VertexAttribute a{k.name, 0, read_vertex_attribute(model_, it->second, k.color, components, name_)};
            std::size_t elements = a.values.size() / std::size_t(components);
            if (elements != m.vertex_count())
                fail(name_, where + ".attributes." + k.gltf + ": " + std::to_string(elements) +
                                " elements, POSITION has " + std::to_string(m.vertex_count()));
            if (components == 3) {
                std::vector<float> rgba(elements * 4, 1.0f);
                for (std::size_t v = 0; v < elements; ++v)
                    for (std::size_t c = 0; c < 3; ++c) rgba[v * 4 + c] = a.values[v * 3 + c];
                a.values.swap(rgba);
                components = 4;
            }
            a.components = components;
            m.attributes.push_back(corners_of(a, m.indices));
        }
    }

    const tinygltf::Model& model_;
    const std::string& name_;
    GltfScene out_;
    std::map<std::pair<int, std::size_t>, std::optional<std::size_t>> prototypes_;
    bool need_triangles_;
    std::uint64_t triangles_ = 0;
    std::string cameras_; ///< the camera nodes met in the walk
};

} // namespace

GltfScene parse_gltf(std::string_view bytes, const std::string& name, bool read_files)
{
    tinygltf::Model model = load_gltf_model(bytes, name, read_files);
    return Walker(model, name).run();
}

GltfScene parse_gltf_cameras(std::string_view bytes, const std::string& name, bool read_files)
{
    tinygltf::Model model = load_gltf_model(bytes, name, read_files);
    return Walker(model, name, false).run();
}

#else

GltfScene parse_gltf(std::string_view, const std::string& name, bool)
{
    fail(name, "cannot read glTF: this build of clvis was made without tinygltf (Debian: libtinygltf-dev)");
}

GltfScene parse_gltf_cameras(std::string_view, const std::string& name, bool)
{
    fail(name, "cannot read glTF: this build of clvis was made without tinygltf (Debian: libtinygltf-dev)");
}

#endif

} // namespace detail

GltfScene load_gltf(const std::string& path)
{
    std::string bytes = detail::read_file(path);
    return detail::parse_gltf(bytes, path, true);
}

} // namespace clvis
