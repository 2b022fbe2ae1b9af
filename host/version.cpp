// The library version, from the project's CMake version.
#include <clvis/config.hpp>
#include <clvis/version.hpp>

namespace clvis {

std::string version() { return CLVIS_VERSION_STRING; }

} // namespace clvis
