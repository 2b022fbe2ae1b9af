// Case folding for names the library matches without regard to case: file extensions (scene and
// image loaders) and device specs. ASCII only; a whole-library helper, header-only.
#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace clvis::detail {

inline std::string lower_case(std::string s)
{
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

/// The extension of the file name in `path`, with its dot, lower-cased: ".obj", or "" for none.
inline std::string lower_extension(const std::string& path)
{
    return lower_case(std::filesystem::path(path).extension().string());
}

} // namespace clvis::detail
