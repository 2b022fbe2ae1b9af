// The cache folder shared by the program binary cache and the tuner (see cache_dir.hpp).
#include "runtime/cache_dir.hpp"

#include <cstdlib>
#include <fstream>
#include <random>
#include <string>

#include <unistd.h>

namespace clvis::detail {

std::filesystem::path cache_dir()
{
    if (const char* dir = std::getenv("CLVIS_CACHE_DIR"); dir && *dir) return dir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::filesystem::path(xdg) / "clvis";
    if (const char* home = std::getenv("HOME"); home && *home) return std::filesystem::path(home) / ".cache" / "clvis";
    return {};
}

bool write_cache_file(const std::filesystem::path& file, const void* bytes, std::size_t size)
{
    std::error_code ec;
    std::filesystem::create_directories(file.parent_path(), ec);
    std::random_device random;
    std::filesystem::path tmp = file;
    tmp += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(random());
    {
        std::ofstream out(tmp, std::ios::binary);
        if (out) out.write(static_cast<const char*>(bytes), std::streamsize(size));
        if (out) out.close();
        if (!out) {
            std::filesystem::remove(tmp, ec);
            return false;
        }
    }
    std::filesystem::rename(tmp, file, ec);
    if (ec) std::filesystem::remove(tmp, ec);
    return !ec;
}

} // namespace clvis::detail
