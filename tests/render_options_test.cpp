// The option enums' names (render_options.hpp, shading.hpp's ShadeMode, attributes.hpp's Attribute,
// camera.hpp's FilmFit, rays.hpp's RayQueryKind): every value
// round-trips through to_string and its *_from_string, option_names<E>() lists them in
// declaration order, and an unknown name is refused with Error(InvalidArgument) naming the
// option, the accepted names and the value given.
#include "catch.hpp"

#include <clvis/attributes.hpp>
#include <clvis/camera.hpp>
#include <clvis/error.hpp>
#include <clvis/rays.hpp>
#include <clvis/render_options.hpp>
#include <clvis/shading.hpp>

#include <string>
#include <vector>

using namespace clvis;

namespace {

/// Checks one enum: `values` in declaration order, `from_string` its named parser, `option` and
/// `listed` what the refusal says.
template <class E>
void check_names(const std::vector<E>& values, E (*from_string)(const std::string&), const std::string& option,
                 const std::string& listed)
{
    const std::vector<std::string>& names = option_names<E>();
    REQUIRE(names.size() == values.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
        CAPTURE(option, names[i]);
        CHECK(names[i] == to_string(values[i]));
        CHECK(from_string(names[i]) == values[i]);
        CHECK(option_from_string<E>(names[i]) == values[i]);
    }
    for (const std::string& bad : {std::string("bogus"), std::string(), names.front() + " ", std::string("AUTO")}) {
        CAPTURE(option, bad);
        try {
            from_string(bad);
            FAIL("an unknown name was accepted");
        } catch (const Error& e) {
            CHECK(e.kind() == Error::Kind::InvalidArgument);
            CHECK(std::string(e.what()) == option + ": expected one of " + listed + ", got '" + bad + "'");
        }
    }
}

} // namespace

TEST_CASE("every option enum round-trips through its names, and an unknown name is refused, listing them",
          "[render_options]")
{
    check_names<Path>({Path::Raster, Path::Ray, Path::Brute}, path_from_string, "path", "raster, ray, brute");
    check_names<Cull>({Cull::None, Cull::Back, Cull::Front}, cull_from_string, "cull", "none, back, front");
    check_names<Coverage>({Coverage::Watertight, Coverage::RasterRule}, coverage_from_string, "coverage",
                          "watertight, raster-rule");
    check_names<BvhUpdate>({BvhUpdate::Refit, BvhUpdate::Rebuild}, bvh_update_from_string, "bvh_update",
                           "refit, rebuild");
    check_names<RasterAtomics>({RasterAtomics::Auto, RasterAtomics::On, RasterAtomics::Off},
                               raster_atomics_from_string, "raster_atomics", "auto, on, off");
    check_names<RasterMapping>({RasterMapping::Auto, RasterMapping::Square, RasterMapping::Pixel},
                               raster_mapping_from_string, "raster_mapping", "auto, square, pixel");
    check_names<RayMapping>({RayMapping::Auto, RayMapping::Packet, RayMapping::Single}, ray_mapping_from_string,
                            "ray_mapping", "auto, packet, single");
    check_names<ShadeMode>({ShadeMode::Lambert, ShadeMode::Depth, ShadeMode::Ids}, shade_mode_from_string, "mode",
                           "lambert, depth, ids");
    check_names<Attribute>({Attribute::Barycentrics, Attribute::Position, Attribute::Normal, Attribute::SmoothNormal},
                           attribute_from_string, "attribute", "barycentrics, position, normal, smooth_normal");
    check_names<FilmFit>({FilmFit::Fill, FilmFit::Overscan}, film_fit_from_string, "fit", "fill, overscan");
    check_names<RayQueryKind>({RayQueryKind::Closest, RayQueryKind::Any, RayQueryKind::Count, RayQueryKind::All},
                              ray_query_kind_from_string, "query", "closest, any, count, all");
}

TEST_CASE("samples per pixel are the powers of two up to 16, and the refusal lists them", "[render_options]")
{
    for (int k = 0; k <= 4; ++k) CHECK(samples_log2(1 << k) == k);
    for (int bad : {0, 3, 32, -1}) {
        CAPTURE(bad);
        CHECK_THROWS_WITH(samples_log2(bad),
                          "samples per pixel must be 1, 2, 4, 8 or 16, got " + std::to_string(bad));
    }
}
