// Names of error kinds and the library version.
#include <clvis/config.hpp>
#include <clvis/error.hpp>
#include <clvis/version.hpp>

namespace clvis {

const char* to_string(Error::Kind kind) noexcept
{
    switch (kind) {
    case Error::Kind::InvalidArgument: return "invalid argument";
    case Error::Kind::Io: return "io";
    case Error::Kind::Device: return "device";
    case Error::Kind::Build: return "build";
    case Error::Kind::Limit: return "limit";
    }
    return "unknown";
}

std::string version() { return CLVIS_VERSION_STRING; }

} // namespace clvis
