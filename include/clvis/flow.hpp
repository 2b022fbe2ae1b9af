// Flow between two views on the device (CONVENTIONS.md "Motion between views (flow)",
// kernels/flow.cl): for each sample of view A, where the point it sees lands in view B, with the
// item transforms of each view (objects that move), whether that is inside B's image and depth
// range (valid) and whether B sees something nearer there (occluded). Computed from A's and B's
// visibility buffers, so both paths give it one meaning; nothing is computed unless asked.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/renderer.hpp>
#include <clvis/views_file.hpp>
#include <clvis/visibility.hpp>

#include <memory>
#include <vector>

namespace clvis {

/// Floats per pixel of a flow buffer: flow.x, flow.y (raster px, x right, y down), valid, occluded
/// (1 or 0); flow NaN and both masks 0 for the background and invalid samples.
constexpr int flow_channels = 4;

/// The flow of one pair of views, on the device: flow_channels floats per pixel of view A, pixels
/// row by row with row 0 on top.
class FlowBuffer {
public:
    int width() const { return width_; }
    int height() const { return height_; }
    bool empty() const { return !buffer_; }
    /// The device buffer (Error(InvalidArgument) when empty).
    cl_mem buffer() const;
    /// Blocking reads: a vector keeps its capacity; a pointer must address width() * height() *
    /// flow_channels floats.
    void read(float* out) const;
    void read(std::vector<float>& out) const;
    std::vector<float> read() const;

private:
    friend struct FlowAccess;
    Device device_;
    std::shared_ptr<struct _cl_mem> buffer_;
    int width_ = 0, height_ = 0;
};

/// The flow from view A (`a`, rendered by `renderer` with `camera_a`) to view B (`b`, `camera_b`),
/// into `target` (its buffer reused when it fits). The triangles' corners at each view are the
/// Renderer's scene (as made or last updated) with `items_a` / `items_b` replacing the
/// transforms of the items they name: how objects move between views; for a scene with
/// instances only the triangles A shows are placed (on the host) and uploaded, never the
/// expansion. Error(InvalidArgument) for an empty buffer, one of another context, buffers of
/// different sizes, more than one sample per pixel, or an item the scene does not have.
void flow(Renderer& renderer, const VisibilityBuffer& a, const Camera& camera_a, const VisibilityBuffer& b,
          const Camera& camera_b, FlowBuffer& target, const ItemTransforms& items_a = {},
          const ItemTransforms& items_b = {});
FlowBuffer flow(Renderer& renderer, const VisibilityBuffer& a, const Camera& camera_a, const VisibilityBuffer& b,
                const Camera& camera_b, const ItemTransforms& items_a = {}, const ItemTransforms& items_b = {});

} // namespace clvis
