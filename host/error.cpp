// Names of error kinds, for messages and logs.
#include <clvis/error.hpp>

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

} // namespace clvis
