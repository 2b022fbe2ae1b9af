// The kernel sources embedded at build time by cmake/embed_kernels.cmake, includes inlined.
#pragma once

#include <string>
#include <vector>

namespace clvis::detail {

struct EmbeddedKernel {
    std::string name;   ///< the file's stem: "raster_fine" for kernels/raster_fine.cl
    std::string source;
};

const std::vector<EmbeddedKernel>& embedded_kernels();
/// The source of kernels/<name>.cl; throws Error(Build) when there is none.
const std::string& embedded_kernel(const std::string& name);

} // namespace clvis::detail
