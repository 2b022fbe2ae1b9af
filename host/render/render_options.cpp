// Names of the paths, of the raster path's depth-test modes and mappings, of the ray path's
// mappings and of the coverage modes, for flags, messages and reports.
#include <clvis/error.hpp>
#include <clvis/render_options.hpp>

namespace clvis {

const char* to_string(Path path) noexcept
{
    switch (path) {
    case Path::Raster: return "raster";
    case Path::Ray: return "ray";
    case Path::Brute: return "brute";
    }
    return "unknown";
}

Path path_from_string(const std::string& name)
{
    for (Path p : {Path::Raster, Path::Ray, Path::Brute})
        if (name == to_string(p)) return p;
    throw Error(Error::Kind::InvalidArgument, "unknown path '" + name + "' (raster, ray or brute)");
}

const char* to_string(RasterAtomics mode) noexcept
{
    switch (mode) {
    case RasterAtomics::Auto: return "auto";
    case RasterAtomics::On: return "on";
    case RasterAtomics::Off: return "off";
    }
    return "unknown";
}

const char* to_string(RasterMapping mapping) noexcept
{
    switch (mapping) {
    case RasterMapping::Auto: return "auto";
    case RasterMapping::Square: return "square";
    case RasterMapping::Pixel: return "pixel";
    }
    return "unknown";
}

const char* to_string(RayMapping mapping) noexcept
{
    switch (mapping) {
    case RayMapping::Auto: return "auto";
    case RayMapping::Packet: return "packet";
    case RayMapping::Single: return "single";
    }
    return "unknown";
}

const char* to_string(Coverage coverage) noexcept
{
    switch (coverage) {
    case Coverage::Watertight: return "watertight";
    case Coverage::RasterRule: return "raster-rule";
    }
    return "unknown";
}

RasterAtomics raster_atomics_from_string(const std::string& name)
{
    for (RasterAtomics m : {RasterAtomics::Auto, RasterAtomics::On, RasterAtomics::Off})
        if (name == to_string(m)) return m;
    throw Error(Error::Kind::InvalidArgument, "unknown raster atomics mode '" + name + "' (auto, on or off)");
}

RasterMapping raster_mapping_from_string(const std::string& name)
{
    for (RasterMapping m : {RasterMapping::Auto, RasterMapping::Square, RasterMapping::Pixel})
        if (name == to_string(m)) return m;
    throw Error(Error::Kind::InvalidArgument, "unknown raster mapping '" + name + "' (auto, square or pixel)");
}

RayMapping ray_mapping_from_string(const std::string& name)
{
    for (RayMapping m : {RayMapping::Auto, RayMapping::Packet, RayMapping::Single})
        if (name == to_string(m)) return m;
    throw Error(Error::Kind::InvalidArgument, "unknown ray mapping '" + name + "' (auto, packet or single)");
}

int samples_log2(int samples)
{
    for (int k = 0; k <= 4; ++k)
        if (samples == 1 << k) return k;
    throw Error(Error::Kind::InvalidArgument,
                "samples per pixel must be 1, 2, 4, 8 or 16, got " + std::to_string(samples));
}

Coverage coverage_from_string(const std::string& name)
{
    for (Coverage c : {Coverage::Watertight, Coverage::RasterRule})
        if (name == to_string(c)) return c;
    throw Error(Error::Kind::InvalidArgument, "unknown coverage '" + name + "' (watertight or raster-rule)");
}

} // namespace clvis
