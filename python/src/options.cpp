// The keyword options of clvis.Renderer and clvis.MultiDeviceRenderer: one table of the
// RenderOptions fields as the command line names them, each with its type and setter; defaults
// are RenderOptions{}'s and the enums' names the library's tables (render_options.hpp).
#include "bindings.hpp"

#include <nanobind/stl/string.h>

#include <functional>
#include <type_traits>

namespace clvis::python {

namespace {

struct Keyword {
    std::string name;
    std::string type;            ///< its Python type in the signature: "int" or "str"
    std::string default_literal; ///< RenderOptions{}'s value as a Python literal
    std::function<void(RenderOptions&, nb::handle)> set;
};

/// `field` selects an int of RenderOptions.
template <class Field>
Keyword int_keyword(const char* name, Field field)
{
    RenderOptions defaults;
    return {name, "int", std::to_string(field(defaults)), [name, field](RenderOptions& o, nb::handle value) {
                int v = 0;
                if (!nb::try_cast(value, v))
                    throw nb::type_error((std::string(name) + ": expected an int, got " +
                                          nb::type_name(value.type()).c_str()).c_str());
                field(o) = v;
            }};
}

/// `field` selects an option enum of RenderOptions, named as option_names<E>() names it.
template <class Field>
Keyword enum_keyword(const char* name, Field field)
{
    using E = std::decay_t<decltype(field(std::declval<RenderOptions&>()))>;
    RenderOptions defaults;
    return {name, "str", "'" + std::string(to_string(field(defaults))) + "'",
            [name, field](RenderOptions& o, nb::handle value) {
                std::string v;
                if (!nb::try_cast(value, v))
                    throw nb::type_error((std::string(name) + ": expected a str, got " +
                                          nb::type_name(value.type()).c_str()).c_str());
                field(o) = option_from_string<E>(v);
            }};
}

/// In the order of the signature (and of the command line's help).
const std::vector<Keyword>& keywords()
{
    static const std::vector<Keyword> table = {
        int_keyword("tile", [](RenderOptions& o) -> int& { return o.tile_size; }),
        enum_keyword("cull", [](RenderOptions& o) -> Cull& { return o.cull; }),
        int_keyword("leaf_size", [](RenderOptions& o) -> int& { return o.bvh.max_leaf_size; }),
        int_keyword("sah_bins", [](RenderOptions& o) -> int& { return o.bvh.sah_bins; }),
        enum_keyword("bvh_update", [](RenderOptions& o) -> BvhUpdate& { return o.bvh.update; }),
        enum_keyword("raster_atomics", [](RenderOptions& o) -> RasterAtomics& { return o.raster_atomics; }),
        enum_keyword("coverage", [](RenderOptions& o) -> Coverage& { return o.coverage; }),
        // Checked by the Renderer: 1, 2, 4, 8 or 16.
        int_keyword("samples", [](RenderOptions& o) -> int& { return o.samples; }),
        enum_keyword("raster_mapping", [](RenderOptions& o) -> RasterMapping& { return o.raster_mapping; }),
        enum_keyword("ray_mapping", [](RenderOptions& o) -> RayMapping& { return o.ray_mapping; }),
        // Checked by the Renderer: 1 to 8 depth layers (render() then gives (H, W, layers) arrays).
        int_keyword("layers", [](RenderOptions& o) -> int& { return o.layers; }),
    };
    return table;
}

} // namespace

RenderOptions render_options(const nb::kwargs& given, const char* what)
{
    RenderOptions o;
    for (const auto& [key, value] : given) {
        const std::string name = nb::cast<std::string>(key);
        const Keyword* k = nullptr;
        for (const Keyword& candidate : keywords())
            if (candidate.name == name) k = &candidate;
        if (!k)
            throw nb::type_error((std::string(what) + "() got an unexpected keyword argument '" + name + "'").c_str());
        k->set(o, value);
    }
    return o;
}

const char* options_signature(const std::string& head)
{
    static std::vector<std::unique_ptr<std::string>> kept; // nanobind keeps the pointer
    std::string sig = "def __init__(self, " + head + ", *";
    for (const Keyword& k : keywords()) sig += ", " + k.name + ": " + k.type + " = " + k.default_literal;
    kept.push_back(std::make_unique<std::string>(sig + ") -> None"));
    return kept.back()->c_str();
}

} // namespace clvis::python
