// Names of the paths, for flags, messages and reports.
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

} // namespace clvis
