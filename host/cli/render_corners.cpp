// clvis render's --attributes, --objects and --normals-space (render_corners.hpp).
#include "render_corners.hpp"

#if CLVIS_WITH_IMAGE_IO
#include <clvis/image_io.hpp>
#endif

namespace clvis::cli {

namespace {

[[noreturn]] void refuse(const std::string& why) { throw Error(Error::Kind::InvalidArgument, why); }

} // namespace

void CornerOutputs::add_to(CLI::App& cmd)
{
    cmd.add_option("--attributes", attributes,
                   "write every named vertex attribute of the scene (uv, color, ...) interpolated at each pixel "
                   "(.exr; float channels NAME.x, NAME.y, ..; NaN on the background and where a mesh lacks it)");
    cmd.add_option("--objects", objects,
                   "write the object id of each pixel: the index of the item (mesh or instance) its triangle belongs "
                   "to (.tif, .tiff, .exr; uint32 channel 'object', background 0xFFFFFFFF)");
    cmd.add_option("--normals-space", normals_space,
                   "the axes of --normals: world (default) or camera (x = r, y = u, z = -f)")
        ->check(CLI::IsMember({"world", "camera"}));
}

void CornerOutputs::check(int samples, bool spread) const
{
    if (objects.empty()) return;
    if (samples != 1)
        refuse("--objects: object ids are resolved at one sample per pixel; --samples " + std::to_string(samples) +
               " is for --ids, --depth, --image and --visible");
    if (spread) refuse("--objects: for one device in one process; --devices and --distribute write --ids and --depth");
}

void CornerOutputs::loaded(const Scene& s)
{
    if (attributes.empty()) return;
    scene = scene_attributes(s);
    if (scene.empty())
        refuse("--attributes: the scene has no vertex attributes (no uv, color or other per-vertex property) to "
               "write to '" + attributes + "'");
}

void CornerOutputs::request(AttributeRequest& r) const
{
    r.normal_space = normal_space_from_string(normals_space);
    r.object = !objects.empty();
    if (!attributes.empty())
        for (const AttributeInfo& a : scene) r.named.push_back(a.name);
}

std::vector<std::string> layer_channels(const std::vector<std::string>& names, int layers)
{
    if (layers == 1) return names;
    std::vector<std::string> all;
    for (int k = 0; k < layers; ++k)
        for (const std::string& name : names) all.push_back("L" + std::to_string(k) + "." + name);
    return all;
}

void CornerOutputs::write(const std::vector<AttributeBuffers>& resolved, int width, int height,
                          const std::function<std::string(const std::string&)>& file_name) const
{
#if CLVIS_WITH_IMAGE_IO
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    const int layers = int(resolved.size());
    if (!attributes.empty()) {
        // Every attribute's components side by side: uv.x, uv.y, color.x, .. in the scene's order.
        std::vector<std::string> channels;
        std::size_t total = 0;
        for (const AttributeInfo& a : scene) total += std::size_t(a.components);
        std::vector<std::vector<float>> all(resolved.size(), std::vector<float>(pixels * total));
        std::vector<float> one;
        std::size_t at = 0;
        for (const AttributeInfo& a : scene) {
            for (int c = 0; c < a.components; ++c) channels.push_back(a.name + "." + "xyzw"[c]);
            for (std::size_t k = 0; k < resolved.size(); ++k) {
                resolved[k].read(a.name, one);
                for (int c = 0; c < a.components; ++c)
                    for (std::size_t i = 0; i < pixels; ++i)
                        all[k][i * total + at + std::size_t(c)] = one[i * std::size_t(a.components) + std::size_t(c)];
            }
            at += std::size_t(a.components);
        }
        write_float_channels(file_name(attributes), width, height, layer_channels(channels, layers),
                             interleave_layers(all, total));
    }
    if (!objects.empty()) {
        std::vector<std::vector<std::uint32_t>> ids(resolved.size());
        for (std::size_t k = 0; k < resolved.size(); ++k) resolved[k].read_objects(ids[k]);
        write_object_ids(file_name(objects), width, height, layers, interleave_layers(ids, 1));
    }
#else
    (void)resolved, (void)width, (void)height, (void)file_name;
    if (!attributes.empty() || !objects.empty())
        refuse(std::string(attributes.empty() ? "--objects" : "--attributes") +
               ": this clvis was built without OpenImageIO (CLVIS_WITH_IMAGE_IO=OFF)");
#endif
}

} // namespace clvis::cli
