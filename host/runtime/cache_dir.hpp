// Where clvis keeps what it learns about devices between runs: program binaries
// (program_cache.cpp) and tuned choices (tune_cache.cpp).
#pragma once

#include <filesystem>

namespace clvis::detail {

/// $CLVIS_CACHE_DIR, else $XDG_CACHE_HOME/clvis, else $HOME/.cache/clvis; empty when none is set
/// (nothing is then kept on disk). The folder may not exist yet.
std::filesystem::path cache_dir();

} // namespace clvis::detail
