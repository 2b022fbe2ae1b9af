// The library's version, as built.
#pragma once

#include <string>

namespace clvis {

/// "MAJOR.MINOR.PATCH" of the library that is linked (not of the headers compiled against).
std::string version();

} // namespace clvis
