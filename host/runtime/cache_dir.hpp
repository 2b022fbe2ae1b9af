// Where clvis keeps what it learns about devices between runs: program binaries
// (program_cache.cpp) and tuned choices (tune_cache.cpp).
#pragma once

#include <cstddef>
#include <filesystem>

namespace clvis::detail {

/// $CLVIS_CACHE_DIR, else $XDG_CACHE_HOME/clvis, else $HOME/.cache/clvis; empty when none is set
/// (nothing is then kept on disk). The folder may not exist yet.
std::filesystem::path cache_dir();

/// Writes `size` bytes to `file` through a temporary beside it with a name of its own (pid and
/// random), renamed over `file` when complete: a reader, or another process writing the same
/// entry at once, never sees half a file. A failure leaves the cache as it was; false then.
bool write_cache_file(const std::filesystem::path& file, const void* bytes, std::size_t size);

} // namespace clvis::detail
