// Interim: the raster path is being written; until it lands, using it throws.
#include "pipeline.hpp"

#include <clvis/error.hpp>

namespace clvis::detail {

struct RasterPipeline::Impl {};
RasterPipeline::RasterPipeline(Device::Impl&, const RenderOptions&)
{
    throw Error(Error::Kind::InvalidArgument, "the raster path is not available in this build yet");
}
RasterPipeline::~RasterPipeline() = default;

} // namespace clvis::detail
namespace clvis::detail {
void RasterPipeline::render(const DeviceScene&, Frame&) {}
}
