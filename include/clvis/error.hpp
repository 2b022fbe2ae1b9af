// clvis::Error: the one exception type of the library. Every failure (a bad argument, a bad
// file, a missing or failing OpenCL device, a kernel that does not build, a limit exceeded)
// surfaces as an Error whose message names what was wrong and where.
#pragma once

#include <stdexcept>
#include <string>

namespace clvis {

class Error : public std::runtime_error {
public:
    enum class Kind {
        InvalidArgument, ///< a value given by the caller is out of its domain (names the value)
        Io,              ///< a file could not be read, parsed or written (names file and line)
        Device,          ///< no OpenCL platform/device, or an OpenCL call failed (names the call)
        Build,           ///< a kernel program failed to build (carries the build log)
        Limit,           ///< a request exceeds what the device or the id format can hold
    };

    Error(Kind kind, const std::string& message) : std::runtime_error(message), kind_(kind) {}

    Kind kind() const noexcept { return kind_; }

private:
    Kind kind_;
};

/// A short lowercase name of an error kind ("invalid argument", "io", ...).
const char* to_string(Error::Kind kind) noexcept;

} // namespace clvis
