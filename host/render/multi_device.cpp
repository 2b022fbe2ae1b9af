// Several devices, one frame (include/clvis/multi_device.hpp): one host thread per device takes
// the next tile from a shared atomic counter until none is left, renders it as a region into a
// buffer of the tile's size on its device, reads it back and copies its rows into the frame. Tiles
// never overlap, so the threads write disjoint keys; the first failure stops every thread.
#include <clvis/multi_device.hpp>

#include <clvis/error.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <mutex>
#include <thread>

namespace clvis {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

/// The tiles of a frame, row by row: tile k's rectangle, cut at the image's right and bottom.
struct TileGrid {
    int width, height, tile, columns, rows;
    TileGrid(int w, int h, int t) : width(w), height(h), tile(t), columns((w + t - 1) / t), rows((h + t - 1) / t) {}
    int count() const { return columns * rows; }
    Region region(int k) const
    {
        int x = (k % columns) * tile, y = (k / columns) * tile;
        return Region{x, y, std::min(tile, width - x), std::min(tile, height - y)};
    }
};

/// A device's buffers of tile sizes (at most four: inner, right, bottom, corner), kept for the frame.
class TileBuffers {
public:
    TileBuffers(const Device& device, int layers) : device_(device), layers_(layers) {}
    VisibilityBuffer& of(int width, int height)
    {
        for (auto& b : buffers_)
            if (b.width() == width && b.height() == height) return b;
        buffers_.emplace_back(device_, width, height, 1, layers_);
        return buffers_.back();
    }

private:
    Device device_;
    int layers_ = 1; ///< RenderOptions::layers: each tile's buffer holds them, layer-major
    std::vector<VisibilityBuffer> buffers_;
};

/// The first failure of any device, kept with the device named.
class FirstFailure {
public:
    bool failed() const { return failed_.load(std::memory_order_relaxed); }
    void keep(std::size_t device, const std::string& name)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!failed_.exchange(true)) {
            error_ = std::current_exception();
            where_ = "device " + std::to_string(device) + " (" + name + "): ";
        }
    }
    void rethrow() const
    {
        if (!failed()) return;
        try {
            std::rethrow_exception(error_);
        } catch (const Error& e) {
            throw Error(e.kind(), where_ + e.what());
        } catch (const std::exception& e) {
            throw Error(Error::Kind::Device, where_ + e.what());
        }
    }

private:
    std::atomic<bool> failed_{false};
    std::mutex mutex_;
    std::exception_ptr error_;
    std::string where_;
};

void check_frame(int width, int height, const MultiDeviceOptions& o)
{
    if (width <= 0 || height <= 0)
        throw Error(Error::Kind::InvalidArgument, "image size must be positive, got " + std::to_string(width) + "x" +
                                                      std::to_string(height));
    if (o.tile < 1 || o.tile > 4096)
        throw Error(Error::Kind::InvalidArgument,
                    "screen tile size must lie in [1, 4096] pixels, got " + std::to_string(o.tile));
}

} // namespace

MultiDeviceRenderer::MultiDeviceRenderer(const std::vector<Device>& devices, const Scene& scene, RenderOptions options)
{
    if (devices.empty() || devices.size() > 255)
        throw Error(Error::Kind::InvalidArgument,
                    "MultiDeviceRenderer: needs 1 to 255 devices, got " + std::to_string(devices.size()));
    if (!options.region.whole())
        throw Error(Error::Kind::InvalidArgument, "MultiDeviceRenderer: options.region must be the whole image "
                                                  "(the renderer cuts the frame into tiles itself)");
    if (options.samples != 1)
        throw Error(Error::Kind::InvalidArgument, "MultiDeviceRenderer: draws one sample per pixel, the options ask for " +
                                                      std::to_string(options.samples));
    for (std::size_t i = 0; i < devices.size(); ++i) {
        try {
            renderers_.emplace_back(devices[i], scene, options);
        } catch (const Error& e) {
            std::string name = devices[i] ? devices[i].info().name : std::string("empty Device");
            throw Error(e.kind(), "device " + std::to_string(i) + " (" + name + "): " + e.what());
        }
    }
}

MultiDeviceRenderer::~MultiDeviceRenderer() = default;
MultiDeviceRenderer::MultiDeviceRenderer(MultiDeviceRenderer&&) noexcept = default;
MultiDeviceRenderer& MultiDeviceRenderer::operator=(MultiDeviceRenderer&&) noexcept = default;

void MultiDeviceRenderer::prepare(Path path)
{
    for (std::size_t i = 0; i < renderers_.size(); ++i) {
        try {
            renderers_[i].prepare(path);
        } catch (const Error& e) {
            throw Error(e.kind(), "device " + std::to_string(i) + " (" + renderers_[i].device().info().name +
                                      "): " + e.what());
        }
    }
}

void MultiDeviceRenderer::render(const Camera& camera, int width, int height, Path path,
                                 const MultiDeviceOptions& options, MultiDeviceFrame& out)
{
    if (renderers_.empty())
        throw Error(Error::Kind::InvalidArgument, "MultiDeviceRenderer::render: the renderer was moved from");
    camera.validate();
    check_frame(width, height, options);
    auto t0 = Clock::now();
    TileGrid grid(width, height, options.tile);
    std::size_t pixels = std::size_t(width) * std::size_t(height);
    out.width = width;
    out.height = height;
    out.tiles = grid.count();
    const int layers = renderers_[0].options().layers; // depth layers: K planes, layer-major
    out.layers = layers;
    out.keys.resize(pixels * std::size_t(layers));
    out.device_of.assign(options.device_map ? pixels : 0, 0);
    out.devices.assign(renderers_.size(), DeviceShare{});
    std::atomic<int> next{0};
    FirstFailure failure;
    auto work = [&](std::size_t d) {
        Renderer& renderer = renderers_[d];
        DeviceShare& share = out.devices[d];
        share.device = renderer.device().info().name;
        share.index = renderer.device().info().index;
        try {
            TileBuffers buffers(renderer.device(), layers);
            std::vector<std::uint64_t> keys;
            for (int k = next++; k < grid.count() && !failure.failed(); k = next++) {
                auto t = Clock::now();
                Region r = grid.region(k);
                VisibilityBuffer& target = buffers.of(r.width, r.height);
                renderer.render(camera, width, height, r, path, target);
                target.read_keys(keys);
                std::size_t tile_plane = std::size_t(r.width) * std::size_t(r.height);
                for (int j = 0; j < r.height; ++j) {
                    std::size_t row = std::size_t(r.y + j) * std::size_t(width) + std::size_t(r.x);
                    for (int l = 0; l < layers; ++l)
                        std::copy_n(keys.begin() + std::ptrdiff_t(l * tile_plane + std::size_t(j) * std::size_t(r.width)),
                                    r.width, out.keys.begin() + std::ptrdiff_t(l * pixels + row));
                    if (options.device_map) std::fill_n(out.device_of.begin() + std::ptrdiff_t(row), r.width, std::uint8_t(d));
                }
                ++share.tiles;
                share.busy_ms += ms_since(t);
            }
        } catch (...) {
            failure.keep(d, share.device);
        }
    };
    std::vector<std::thread> threads;
    try {
        for (std::size_t d = 1; d < renderers_.size(); ++d) threads.emplace_back(work, d);
    } catch (...) { // no thread for the next device: stop the others, join them, report it
        failure.keep(threads.size() + 1, renderers_[threads.size() + 1].device().info().name);
    }
    work(0); // this thread drives the first device (it stops at once after a failure)
    for (auto& t : threads) t.join();
    failure.rethrow();
    out.frame_ms = ms_since(t0);
}

MultiDeviceFrame MultiDeviceRenderer::render(const Camera& camera, int width, int height, Path path,
                                             const MultiDeviceOptions& options)
{
    MultiDeviceFrame frame;
    render(camera, width, height, path, options, frame);
    return frame;
}

std::size_t MultiDeviceRenderer::device_count() const { return renderers_.size(); }

Renderer& MultiDeviceRenderer::renderer(std::size_t index)
{
    if (index >= renderers_.size())
        throw Error(Error::Kind::InvalidArgument, "MultiDeviceRenderer::renderer: no device " + std::to_string(index) +
                                                      " of " + std::to_string(renderers_.size()));
    return renderers_[index];
}

} // namespace clvis
