// The resolved files of `clvis render --layers K` (CONVENTIONS.md "Depth layers", "Barycentrics",
// "Vertex attributes", "Object ids"), read back through OpenImageIO as raw 32-bit words. Run by
// layers_cli.cmake as `layers_files_check DIR K MESH...` once it has written in DIR, for the
// scene MESH... (one item per file, in order) and one camera:
//   one-*.exr       --layers 1 --path raster: bary, attr (--attributes), obj (--objects),
//                   normals (--normals), position (--position)
//   k.exr           --layers K --path raster: ids (L0.id ..)
//   k-*.exr, k-obj.tif   the same outputs as one-*, with --layers K
//   rule-*.exr      --layers K --path ray --coverage raster-rule: bary, attr, obj
// Checks: the channel names (no prefix with one layer; L{k}.<channel> with K); layer 0 equal to
// the one-layer files bit for bit; layer k's object ids the items of layer k's triangle ids (the
// TIFF's channels in layer order); background layers u = v = 0 and NaN attributes, normals and
// positions; covered ones finite, uv NaN exactly on items without uv; layers behind the first
// holding surfaces of every item; the raster-rule ray files equal the raster ones bit for bit.
#include <clvis/host_visibility.hpp>
#include <clvis/scene.hpp>
#include <clvis/scene_io.hpp>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

namespace {

int failures = 0;

void fail(const std::string& what)
{
    if (++failures <= 40) std::cerr << "layers_files_check: " << what << "\n";
}

/// A file's channels as raw 32-bit words (floats by their bits), the channels of a pixel adjacent.
struct File {
    std::string path;
    int width = 0, height = 0;
    std::vector<std::string> names;
    std::vector<std::uint32_t> words;

    std::size_t pixels() const { return std::size_t(width) * std::size_t(height); }
    /// The channel `name` (the `index`-th when `name` is empty), one word per pixel.
    std::vector<std::uint32_t> channel(const std::string& name, std::size_t index = 0) const
    {
        if (!name.empty()) index = std::size_t(std::find(names.begin(), names.end(), name) - names.begin());
        std::vector<std::uint32_t> plane;
        if (index >= names.size()) {
            fail(path + ": no channel '" + name + "'");
            return std::vector<std::uint32_t>(pixels(), 0);
        }
        for (std::size_t i = 0; i < pixels(); ++i) plane.push_back(words[i * names.size() + index]);
        return plane;
    }
};

File read(const std::string& path, OIIO::TypeDesc type)
{
    File f;
    f.path = path;
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        fail(path + ": cannot read: " + OIIO::geterror());
        return f;
    }
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.format != type) fail(path + ": holds " + std::string(spec.format.c_str()) + ", not " + type.c_str());
    f.width = spec.width;
    f.height = spec.height;
    f.names = spec.channelnames;
    f.words.resize(f.pixels() * std::size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, type, f.words.data())) fail(path + ": " + in->geterror());
    return f;
}

float as_float(std::uint32_t w)
{
    float f;
    std::memcpy(&f, &w, sizeof f);
    return f;
}

std::vector<std::string> layer_names(const std::vector<std::string>& names, int layers)
{
    std::vector<std::string> all;
    for (int k = 0; k < layers; ++k)
        for (const std::string& n : names) all.push_back("L" + std::to_string(k) + "." + n);
    return all;
}

void same_names(const File& f, std::vector<std::string> want)
{
    std::vector<std::string> got = f.names;
    std::sort(got.begin(), got.end());
    std::sort(want.begin(), want.end());
    if (got != want) {
        std::string g, w;
        for (const auto& n : got) g += " " + n;
        for (const auto& n : want) w += " " + n;
        fail(f.path + ": channels" + g + ", not" + w);
    }
}

/// Every channel of `b` equal to `a`'s of the same name, bit for bit (`prefix` added to a's names).
void same_bits(const File& a, const File& b, const std::string& prefix)
{
    for (const std::string& name : a.names)
        if (a.channel(name) != b.channel(prefix + name))
            fail(b.path + ": channel '" + prefix + name + "' differs from '" + name + "' of " + a.path);
}

} // namespace

int main(int argc, char** argv)
{
    if (argc < 4) {
        std::cerr << "usage: layers_files_check DIR K MESH...\n";
        return 2;
    }
    const std::string dir = std::string(argv[1]) + "/";
    const int layers = std::stoi(argv[2]);
    std::vector<std::string> meshes(argv + 3, argv + argc);
    clvis::Scene scene = clvis::load_scene(meshes);
    std::vector<bool> has_uv; // per item: one item per mesh file
    for (const std::string& m : meshes) {
        clvis::MeshData mesh = clvis::load_mesh(m);
        has_uv.push_back(std::any_of(mesh.attributes.begin(), mesh.attributes.end(),
                                     [](const clvis::CornerAttribute& a) { return a.name == "uv"; }));
    }
    const OIIO::TypeDesc F = OIIO::TypeDesc::FLOAT, U = OIIO::TypeDesc::UINT32;
    const struct {
        const char* file;
        std::vector<std::string> channels;
        OIIO::TypeDesc type;
    } outputs[] = {{"bary", {"u", "v"}, F},       {"attr", {"uv.x", "uv.y"}, F},        {"obj", {"object"}, U},
                   {"normals", {"x", "y", "z"}, F}, {"position", {"x", "y", "z"}, F}};
    std::vector<File> deep;
    for (const auto& o : outputs) {
        File one = read(dir + "one-" + o.file + ".exr", o.type);
        File k = read(dir + "k-" + o.file + ".exr", o.type);
        same_names(one, o.channels);
        same_names(k, layer_names(o.channels, layers));
        same_bits(one, k, "L0.");
        if (std::string(o.file) != "normals" && std::string(o.file) != "position") {
            File rule = read(dir + "rule-" + o.file + ".exr", o.type);
            same_names(rule, k.names);
            same_bits(k, rule, "");
        }
        deep.push_back(k);
    }
    const File& bary = deep[0];
    const File& attr = deep[1];
    const File& obj = deep[2];
    const File& normals = deep[3];
    const File& position = deep[4];
    File ids = read(dir + "k.exr", U);
    File tif = read(dir + "k-obj.tif", U);
    if (tif.names.size() != std::size_t(layers)) fail(tif.path + ": not one channel per layer");
    for (const File* f : std::vector<const File*>{&bary, &attr, &obj, &normals, &position, &tif})
        if (f->width != ids.width || f->height != ids.height) fail(f->path + ": not the size of " + ids.path);
    if (failures) return 1; // names or sizes wrong: the values cannot be read by layer

    std::size_t behind = 0;
    std::vector<std::size_t> items_seen(meshes.size(), 0);
    auto is_nan = [](std::uint32_t w) { return std::isnan(as_float(w)); };
    auto finite = [](std::uint32_t w) { return std::isfinite(as_float(w)); };
    for (int k = 0; k < layers; ++k) {
        const std::string L = "L" + std::to_string(k) + ".";
        auto id = ids.channel(L + "id"), object = obj.channel(L + "object"), in_tif = tif.channel("", std::size_t(k));
        auto u = bary.channel(L + "u"), v = bary.channel(L + "v");
        auto uvx = attr.channel(L + "uv.x"), uvy = attr.channel(L + "uv.y");
        std::vector<std::vector<std::uint32_t>> vectors;
        for (const char* c : {"x", "y", "z"}) {
            vectors.push_back(normals.channel(L + c));
            vectors.push_back(position.channel(L + c));
        }
        for (std::size_t i = 0; i < ids.pixels(); ++i) {
            const std::string at = "layer " + std::to_string(k) + ", pixel " + std::to_string(i);
            const bool empty = id[i] == clvis::background_id;
            const std::uint32_t item = empty ? clvis::background_id : std::uint32_t(scene.mesh_of(id[i]));
            if (object[i] != item) fail(obj.path + ": " + at + " names item " + std::to_string(object[i]));
            if (in_tif[i] != object[i]) fail(tif.path + ": " + at + " differs from " + obj.path);
            if (empty) {
                if (as_float(u[i]) != 0.0f || as_float(v[i]) != 0.0f) fail(bary.path + ": " + at + ": background not 0, 0");
                if (!is_nan(uvx[i]) || !is_nan(uvy[i])) fail(attr.path + ": " + at + ": background not NaN");
                for (const auto& c : vectors)
                    if (!is_nan(c[i])) fail(at + ": a background normal or position is not NaN");
                continue;
            }
            behind += k > 0;
            if (k > 0) ++items_seen[item];
            if (!finite(u[i]) || !finite(v[i])) fail(bary.path + ": " + at + ": not finite");
            for (const auto& c : vectors)
                if (!finite(c[i])) fail(at + ": a normal or position is not finite");
            if (has_uv[item] != (finite(uvx[i]) && finite(uvy[i])) || is_nan(uvx[i]) != is_nan(uvy[i]))
                fail(attr.path + ": " + at + ": uv of item " + std::to_string(item) +
                     (has_uv[item] ? " is not finite" : " is not NaN"));
        }
    }
    if (behind < 100) fail("only " + std::to_string(behind) + " covered samples behind layer 0");
    for (std::size_t m = 0; m < meshes.size(); ++m)
        if (items_seen[m] == 0) fail(meshes[m] + ": seen in no layer behind the first");
    std::cout << "layers_files_check: " << layers << " layers, " << behind << " covered samples behind layer 0 (";
    for (std::size_t m = 0; m < meshes.size(); ++m) std::cout << (m ? ", " : "") << items_seen[m] << " of item " << m;
    std::cout << "), " << failures << " failures\n";
    return failures ? 1 : 0;
}
