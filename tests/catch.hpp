// Catch2 2.x (Debian 12) or 3.x (Ubuntu 24.04): the same suite builds on both.
// CLVIS_CATCH2_MAJOR is the major version of the Catch2 that CMake found (tests/CMakeLists.txt), so
// the headers are those of the library linked even where both versions are installed (the GPU
// run carries Debian's 2.x beside an image that may hold 3.x); without it, __has_include decides.
#pragma once

#if defined(CLVIS_CATCH2_MAJOR)
#define CLVIS_CATCH2_V3 (CLVIS_CATCH2_MAJOR >= 3)
#elif __has_include(<catch2/catch_all.hpp>)
#define CLVIS_CATCH2_V3 1
#else
#define CLVIS_CATCH2_V3 0
#endif

#if CLVIS_CATCH2_V3
#include <catch2/catch_all.hpp>

#include <string>

// The 2.x spellings the tests use, kept for 3.x: Catch::Contains (3.x's
// Catch::Matchers::ContainsSubstring; 3.x's own Catch::Matchers::Contains matches range
// elements), Catch::StartsWith, and Approx outside namespace Catch.
namespace Catch {
inline Matchers::StringContainsMatcher Contains(const std::string& text,
                                                CaseSensitive sensitivity = CaseSensitive::Yes)
{
    return Matchers::ContainsSubstring(text, sensitivity);
}
using Matchers::StartsWith;
} // namespace Catch
using Catch::Approx;
#else
#include <catch2/catch.hpp>
#endif
