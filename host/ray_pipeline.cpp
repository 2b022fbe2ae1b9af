// Interim: the ray path is being written; until it lands, using it throws.
#include "pipeline.hpp"

#include <clvis/error.hpp>

namespace clvis::detail {

struct RayPipeline::Impl {};
RayPipeline::RayPipeline(Device::Impl&, const RenderOptions&)
{
    throw Error(Error::Kind::InvalidArgument, "the ray path is not available in this build yet");
}
RayPipeline::~RayPipeline() = default;

} // namespace clvis::detail
namespace clvis::detail {
void RayPipeline::build(const Scene&, cl::CommandQueue&) {}
void RayPipeline::update(const Scene&, cl::CommandQueue&) {}
bool RayPipeline::built() const { return false; }
const BvhStats& RayPipeline::stats() const { static BvhStats s; return s; }
void RayPipeline::render(const DeviceScene&, Frame&, bool) {}
}
