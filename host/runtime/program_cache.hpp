// The on-disk cache of built programs (device.cpp's Device::Impl::program): a program's binary,
// loaded instead of building from source. Drivers that cache compiled programs themselves (PoCL)
// still run their compiler front end on every source build, while handing out a binary makes
// PoCL compile every kernel of the program at once, which makes a cold build slower. So their
// binaries are kept only once a program has been built from source before (a marker file says
// so): a first run costs what it did, the second pays for the binary once, and later runs load
// it.
#pragma once

#include "runtime/cl.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace clvis::detail {

class ProgramCache {
public:
    /// The cache entry of a program named `name` whose source, options and device hash to `key`;
    /// no entry (nothing read or written) when cache_dir() is empty. `driver_caches`: the driver
    /// keeps compiled programs of its own (see above).
    ProgramCache(const std::string& name, const std::string& key, bool driver_caches);

    /// The cached program built for `device` with `options`, or none (no entry, or a stale or
    /// foreign binary the driver refuses).
    std::optional<cl::Program> load(const cl::Context& context, const cl::Device& device,
                                    const std::string& options) const;

    /// Records a program just built from source: its binary is kept at once, or (a driver that
    /// caches) once it has been built from source before.
    void built(const cl::Program& program) const;

private:
    std::filesystem::path binary_; ///< empty: no cache
    bool driver_caches_;
};

} // namespace clvis::detail
