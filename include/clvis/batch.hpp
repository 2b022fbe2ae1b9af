// Many views per call: a batch of cameras of one size rendered into one device buffer of keys,
// with the scene, the BVH and the kernels reused and the batch's fixed costs paid once. The ray
// path traces every view in one launch; the raster path runs its stages view after view (its
// host reads the counts of each view's bins), on one queue with one wait. Each view of a batch is
// bit-identical to the same view rendered alone.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/renderer.hpp>
#include <clvis/views_file.hpp>
#include <clvis/visibility.hpp>


#include <memory>
#include <vector>

namespace clvis {

class VisibilityBatch {
public:
    VisibilityBatch() = default;
    /// `views` visibility buffers of width x height in one allocation. Error(InvalidArgument) for
    /// sizes <= 0, Error(Limit) past the device's largest allocation.
    VisibilityBatch(const Device& device, int views, int width, int height);
    /// With `layers` depth layers per view (RenderOptions::layers, 1 to 8): each view a buffer of
    /// that many layers, laid out as VisibilityBuffer lays them.
    VisibilityBatch(const Device& device, int views, int width, int height, int layers);

    int views() const { return int(buffers_.size()); }
    int width() const { return width_; }
    int height() const { return height_; }
    int layers() const { return layers_; } ///< depth layers per view
    /// All keys on the device: view v's width * height (* layers) keys start at key v * stride().
    cl_mem keys() const;
    /// Keys from one view to the next: width * height * layers rounded up to the device's
    /// sub-buffer alignment.
    std::size_t stride() const { return stride_; }
    /// View v as a VisibilityBuffer (a sub-buffer of keys()): read it, shade it, resolve its
    /// attributes or mark a visible set with it, on the device or into the caller's storage.
    const VisibilityBuffer& view(int v) const;

private:
    Device device_;
    std::shared_ptr<struct _cl_mem> keys_;
    std::vector<VisibilityBuffer> buffers_;
    int width_ = 0, height_ = 0;
    std::size_t stride_ = 0;
    int layers_ = 1;
};

/// Renders `cameras` (all validated first) into `target`, whose view count and size fix the
/// batch's (Error(InvalidArgument) when the camera count differs). renderer.last_frame() then
/// times the whole batch: frame_ms from the first enqueue to the end, each stage's kernel times
/// summed over the views.
void render_views(Renderer& renderer, const std::vector<Camera>& cameras, Path path, VisibilityBatch& target);

/// The same for views whose items move (a views file's "items"): view v is rendered with
/// `items[v]`'s transforms replacing `scene`'s, `scene` being the Renderer's scene as it was made or
/// last updated. Consecutive views with the same transforms are one batch as above; between two
/// such runs `scene` is changed and the Renderer updated (Renderer::update). Both are left with
/// `scene`'s transforms as given. Without any item moved this is render_views above, at its cost.
/// Error(InvalidArgument) when items.size() differs from the camera count or names no item.
void render_views(Renderer& renderer, Scene& scene, const std::vector<Camera>& cameras,
                  const std::vector<ItemTransforms>& items, Path path, VisibilityBatch& target);

} // namespace clvis
