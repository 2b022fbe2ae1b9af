// Files written by tests into a folder of their own under the system's temporary directory.
#pragma once

#include <cstdint>
#include <cstdlib>
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

/// Sets an environment variable for its lifetime (nullptr: unsets it), then restores what was there.
struct ScopedEnv {
    std::string name, saved;
    bool had = false;
    ScopedEnv(const char* variable, const char* value) : name(variable)
    {
        if (const char* v = std::getenv(variable)) {
            saved = v;
            had = true;
        }
        if (value) setenv(variable, value, 1);
        else unsetenv(variable);
    }
    ~ScopedEnv()
    {
        if (had) setenv(name.c_str(), saved.c_str(), 1);
        else unsetenv(name.c_str());
    }
    ScopedEnv(const ScopedEnv&) = delete;
    ScopedEnv& operator=(const ScopedEnv&) = delete;
};

/// A new empty folder <tmp>/<name> (emptied when it exists).
inline std::filesystem::path fresh_temp_dir(const std::string& name)
{
    std::filesystem::path p = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(p);
    std::filesystem::create_directories(p);
    return p;
}

/// `bytes` in base64 (RFC 4648, padded): a glTF buffer embedded as a data URI.
inline std::string base64(const std::string& bytes)
{
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t n = std::uint32_t(std::uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) n |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) n |= std::uint32_t(std::uint8_t(bytes[i + 2]));
        out += digits[n >> 18 & 63];
        out += digits[n >> 12 & 63];
        out += i + 1 < bytes.size() ? digits[n >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? digits[n & 63] : '=';
    }
    return out;
}

} // namespace clvis::test
