// The cache folder shared by the program binary cache and the tuner (see cache_dir.hpp).
#include "runtime/cache_dir.hpp"

#include <cstdlib>

namespace clvis::detail {

std::filesystem::path cache_dir()
{
    if (const char* dir = std::getenv("CLVIS_CACHE_DIR"); dir && *dir) return dir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::filesystem::path(xdg) / "clvis";
    if (const char* home = std::getenv("HOME"); home && *home) return std::filesystem::path(home) / ".cache" / "clvis";
    return {};
}

} // namespace clvis::detail
