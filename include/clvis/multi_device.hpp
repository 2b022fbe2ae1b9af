// Several OpenCL devices in one process: the scene uploaded once per device (one Renderer each),
// the screen cut into square tiles handed out from one shared counter to one host thread per
// device (a slower device takes fewer), each tile rendered as a region and copied into one host
// buffer of keys. A region holds the bits of the whole render's pixels, so the frame is
// bit-identical to one device rendering it, whatever device drew which tile.
#pragma once

#include <clvis/camera.hpp>
#include <clvis/device.hpp>
#include <clvis/render_options.hpp>
#include <clvis/renderer.hpp>
#include <clvis/scene.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace clvis {

struct MultiDeviceOptions {
    int tile = 64;          ///< screen tile edge in pixels, in [1, 4096]; edge tiles are cut to the image
    bool device_map = false; ///< record which device drew each pixel (MultiDeviceFrame::device_of)
};

/// What one device did for a frame.
struct DeviceShare {
    std::string device;   ///< its name (DeviceInfo::name): two devices of one kind share it
    std::size_t index = 0; ///< its DeviceInfo::index (position in list_devices()), which tells them apart
    int tiles = 0;        ///< tiles it drew
    double busy_ms = 0;   ///< host wall time in its tiles' renders and read-backs
};

struct MultiDeviceFrame {
    int width = 0, height = 0;
    std::vector<std::uint64_t> keys;     ///< width * height keys, row 0 on top (times `layers`, layer-major)
    int layers = 1;                      ///< depth layers (RenderOptions::layers), as VisibilityBuffer lays them out
    std::vector<std::uint8_t> device_of; ///< with device_map: per pixel, the index of the device that drew it
    std::vector<DeviceShare> devices;    ///< in the renderer's device order
    int tiles = 0;                       ///< tiles in the frame
    double frame_ms = 0;                 ///< host wall time of the whole frame
};

class MultiDeviceRenderer {
public:
    /// One Renderer per device, each with its own copy of the scene (and, once the ray path is
    /// used, its own BVH). A device may appear twice (two queues on it). Throws
    /// Error(InvalidArgument) for an empty list or more than 255 devices, and what a Renderer
    /// throws, with the device named.
    MultiDeviceRenderer(const std::vector<Device>& devices, const Scene& scene, RenderOptions options = {});
    ~MultiDeviceRenderer();
    MultiDeviceRenderer(MultiDeviceRenderer&&) noexcept;
    MultiDeviceRenderer& operator=(MultiDeviceRenderer&&) noexcept;

    /// Builds what `path` needs on every device (kernels, BVH) before the first frame.
    void prepare(Path path);

    /// Renders a width x height frame into `out` (its vectors reused). A device that fails stops
    /// the frame: Error of the failure's kind, its message starting with the device's index and
    /// name, after every thread has stopped; no partial frame is returned as whole.
    void render(const Camera& camera, int width, int height, Path path, const MultiDeviceOptions& options,
                MultiDeviceFrame& out);
    MultiDeviceFrame render(const Camera& camera, int width, int height, Path path,
                            const MultiDeviceOptions& options = {});

    std::size_t device_count() const;
    /// The Renderer of device `index` (its options, BVH statistics, last tile's timing).
    Renderer& renderer(std::size_t index);

private:
    std::vector<Renderer> renderers_;
};

} // namespace clvis
