// Files written by tests into a folder of their own under the system's temporary directory.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace clvis::test {

/// Writes `bytes` to <tmp>/<folder>/<name> (folders created) and returns the path.
inline std::string write_temp_file(const std::string& folder, const std::string& name, const std::string& bytes)
{
    std::filesystem::path p = std::filesystem::temp_directory_path() / folder / name;
    std::filesystem::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    return p.string();
}

} // namespace clvis::test
