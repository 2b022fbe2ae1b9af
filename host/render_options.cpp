// Names of every option enum (paths, culling, coverage, BVH updates, the raster path's depth-test
// modes and mappings, the ray path's mappings, shading modes, attributes, film fits, ray
// queries), one table each, for flags, bindings, messages and reports; and the sample counts of kernels/shared/samples.h.
#include <clvis/attributes.hpp>
#include <clvis/camera.hpp>
#include <clvis/error.hpp>
#include <clvis/rays.hpp>
#include <clvis/render_options.hpp>
#include <clvis/shading.hpp>

#include "shared/samples.h"

#include <utility>

namespace clvis {

namespace {

/// One option enum's names: `option` names the option in messages (the RenderOptions field as
/// Python spells it), `values` every value with its name, in declaration order.
template <class E>
struct Names;

template <>
struct Names<Path> {
    static constexpr const char* option = "path";
    static constexpr std::pair<Path, const char*> values[] = {
        {Path::Raster, "raster"}, {Path::Ray, "ray"}, {Path::Brute, "brute"}};
};

template <>
struct Names<Cull> {
    static constexpr const char* option = "cull";
    static constexpr std::pair<Cull, const char*> values[] = {
        {Cull::None, "none"}, {Cull::Back, "back"}, {Cull::Front, "front"}};
};

template <>
struct Names<Coverage> {
    static constexpr const char* option = "coverage";
    static constexpr std::pair<Coverage, const char*> values[] = {
        {Coverage::Watertight, "watertight"}, {Coverage::RasterRule, "raster-rule"}};
};

template <>
struct Names<BvhUpdate> {
    static constexpr const char* option = "bvh_update";
    static constexpr std::pair<BvhUpdate, const char*> values[] = {
        {BvhUpdate::Refit, "refit"}, {BvhUpdate::Rebuild, "rebuild"}};
};

template <>
struct Names<RasterAtomics> {
    static constexpr const char* option = "raster_atomics";
    static constexpr std::pair<RasterAtomics, const char*> values[] = {
        {RasterAtomics::Auto, "auto"}, {RasterAtomics::On, "on"}, {RasterAtomics::Off, "off"}};
};

template <>
struct Names<RasterMapping> {
    static constexpr const char* option = "raster_mapping";
    static constexpr std::pair<RasterMapping, const char*> values[] = {
        {RasterMapping::Auto, "auto"}, {RasterMapping::Square, "square"}, {RasterMapping::Pixel, "pixel"}};
};

template <>
struct Names<RayMapping> {
    static constexpr const char* option = "ray_mapping";
    static constexpr std::pair<RayMapping, const char*> values[] = {
        {RayMapping::Auto, "auto"}, {RayMapping::Packet, "packet"}, {RayMapping::Single, "single"}};
};

template <>
struct Names<ShadeMode> {
    static constexpr const char* option = "mode"; // ShadeOptions::mode
    static constexpr std::pair<ShadeMode, const char*> values[] = {
        {ShadeMode::Lambert, "lambert"}, {ShadeMode::Depth, "depth"}, {ShadeMode::Ids, "ids"}};
};

template <>
struct Names<Attribute> {
    static constexpr const char* option = "attribute"; // resolve's attributes
    static constexpr std::pair<Attribute, const char*> values[] = {{Attribute::Barycentrics, "barycentrics"},
                                                                   {Attribute::Position, "position"},
                                                                   {Attribute::Normal, "normal"},
                                                                   {Attribute::SmoothNormal, "smooth_normal"}};
};

template <>
struct Names<FilmFit> {
    static constexpr const char* option = "fit"; // Camera::physical's fit
    static constexpr std::pair<FilmFit, const char*> values[] = {{FilmFit::Fill, "fill"}, {FilmFit::Overscan, "overscan"}};
};

template <>
struct Names<RayQueryKind> {
    static constexpr const char* option = "query"; // clvis rays --query
    static constexpr std::pair<RayQueryKind, const char*> values[] = {
        {RayQueryKind::Closest, "closest"}, {RayQueryKind::Any, "any"}, {RayQueryKind::Count, "count"},
        {RayQueryKind::All, "all"}};
};

template <class E>
const char* name_of(E value) noexcept
{
    for (const auto& [e, name] : Names<E>::values)
        if (e == value) return name;
    return "unknown";
}

} // namespace

template <class E>
const std::vector<std::string>& option_names()
{
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const auto& entry : Names<E>::values) v.push_back(entry.second);
        return v;
    }();
    return names;
}

template <class E>
E option_from_string(const std::string& name)
{
    std::string listed;
    for (const auto& [e, n] : Names<E>::values) {
        if (name == n) return e;
        listed += (listed.empty() ? "" : ", ") + std::string(n);
    }
    throw Error(Error::Kind::InvalidArgument,
                std::string(Names<E>::option) + ": expected one of " + listed + ", got '" + name + "'");
}

#define CLVIS_OPTION_NAMES(E, from_string)                                                                  \
    template const std::vector<std::string>& option_names<E>();                                             \
    template E option_from_string<E>(const std::string&);                                                   \
    const char* to_string(E value) noexcept { return name_of(value); }                                      \
    E from_string(const std::string& name) { return option_from_string<E>(name); }

CLVIS_OPTION_NAMES(Path, path_from_string)
CLVIS_OPTION_NAMES(Cull, cull_from_string)
CLVIS_OPTION_NAMES(Coverage, coverage_from_string)
CLVIS_OPTION_NAMES(BvhUpdate, bvh_update_from_string)
CLVIS_OPTION_NAMES(RasterAtomics, raster_atomics_from_string)
CLVIS_OPTION_NAMES(RasterMapping, raster_mapping_from_string)
CLVIS_OPTION_NAMES(RayMapping, ray_mapping_from_string)
CLVIS_OPTION_NAMES(ShadeMode, shade_mode_from_string)
CLVIS_OPTION_NAMES(Attribute, attribute_from_string)
CLVIS_OPTION_NAMES(FilmFit, film_fit_from_string)
CLVIS_OPTION_NAMES(RayQueryKind, ray_query_kind_from_string)

#undef CLVIS_OPTION_NAMES

int samples_log2(int samples)
{
    std::string listed;
    for (int k = 0; k <= CLVIS_MAX_SAMPLES_LOG2; ++k) {
        if (samples == 1 << k) return k;
        listed += (k == 0 ? "" : k < CLVIS_MAX_SAMPLES_LOG2 ? ", " : " or ") + std::to_string(1 << k);
    }
    throw Error(Error::Kind::InvalidArgument,
                "samples per pixel must be " + listed + ", got " + std::to_string(samples));
}

void check_layers(int layers)
{
    if (layers < 1 || layers > 8)
        throw Error(Error::Kind::InvalidArgument, "layers must lie in [1, 8], got " + std::to_string(layers));
}

} // namespace clvis
