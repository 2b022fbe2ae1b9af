// Several devices in one process (MultiDeviceRenderer): tiles drawn by whichever device takes
// them assemble into the keys of one device rendering the frame, bit for bit, on both paths, for
// every tile size and odd image sizes; each pixel's device is recorded; failures name the device.
// The CTest entry gives PoCL two CPU devices (POCL_DEVICES); with one, it is opened twice.
#include "catch.hpp"

#include <clvis/clvis.hpp>
#include <clvis/multi_device.hpp>
#include <clvis/procedural.hpp>
#include <clvis/scene_io.hpp>

#include <cstdint>
#include <string>
#include <vector>

using namespace clvis;

namespace {

/// Every CPU device listed, or the one CPU device twice (two Renderers on it).
std::vector<Device> cpu_devices()
{
    std::vector<Device> out;
    for (const DeviceInfo& info : list_devices())
        if (info.type == DeviceType::Cpu) out.push_back(Device::open(std::to_string(info.index)));
    REQUIRE(!out.empty());
    if (out.size() == 1) out.push_back(Device::open(std::to_string(out[0].info().index)));
    return out;
}

Scene mixed_scene()
{
    Scene s;
    s.add_mesh(load_mesh(std::string(CLVIS_SOURCE_DIR) + "/scenes/spot.obj"));
    Mat4 right = Mat4::identity();
    right(0, 3) = 1.2;
    s.add_mesh(make_soup(2000, 11), right);
    s.add_mesh(make_grid(800, 3));
    return s;
}

} // namespace

TEST_CASE("tiles drawn by several devices are bit-identical to one device's frame", "[device][multi_device]")
{
    std::vector<Device> devices = cpu_devices();
    Scene scene = mixed_scene();
    Camera camera = Camera::framing(scene.bounds());
    Renderer one(devices[0], scene);
    MultiDeviceRenderer many(devices, scene);
    REQUIRE(many.device_count() == devices.size());
    for (Path path : {Path::Raster, Path::Ray}) {
        for (auto [width, height] : {std::pair{157, 93}, std::pair{61, 1}, std::pair{1, 37}}) {
            std::vector<std::uint64_t> want = one.render(camera, width, height, path).read_keys();
            for (int tile : {1, 7, 32, 500}) {
                if (tile == 1 && width * height > 200) continue; // one launch per pixel: small images only
                CAPTURE(to_string(path), width, height, tile);
                MultiDeviceOptions o;
                o.tile = tile;
                o.device_map = true;
                MultiDeviceFrame f = many.render(camera, width, height, path, o);
                REQUIRE(f.width == width);
                REQUIRE(f.keys.size() == want.size());
                std::size_t differ = 0;
                for (std::size_t i = 0; i < want.size(); ++i) differ += f.keys[i] != want[i];
                CHECK(differ == 0);
                int columns = (width + tile - 1) / tile, rows = (height + tile - 1) / tile;
                CHECK(f.tiles == columns * rows);
                int drawn = 0;
                for (const DeviceShare& d : f.devices) drawn += d.tiles;
                CHECK(drawn == f.tiles);
                // Every pixel of a tile was drawn by one device, one that counts the tile.
                REQUIRE(f.device_of.size() == want.size());
                for (int k = 0; k < f.tiles; ++k) {
                    int x = (k % columns) * tile, y = (k / columns) * tile;
                    std::uint8_t d = f.device_of[std::size_t(y) * std::size_t(width) + std::size_t(x)];
                    REQUIRE(d < f.devices.size());
                    CHECK(f.devices[d].tiles > 0);
                    for (int j = y; j < std::min(y + tile, height); ++j)
                        for (int i = x; i < std::min(x + tile, width); ++i)
                            REQUIRE(f.device_of[std::size_t(j) * std::size_t(width) + std::size_t(i)] == d);
                }
            }
        }
    }
}

TEST_CASE("several devices share the tiles of a frame of many tiles", "[device][multi_device]")
{
    std::vector<Device> devices = cpu_devices();
    Scene scene = mixed_scene();
    MultiDeviceRenderer many(devices, scene);
    many.prepare(Path::Ray);
    MultiDeviceOptions o;
    o.tile = 8;
    MultiDeviceFrame f = many.render(Camera::framing(scene.bounds()), 256, 128, Path::Ray, o);
    CHECK(f.tiles == 32 * 16);
    CHECK(f.device_of.empty());
    for (const DeviceShare& d : f.devices) {
        CHECK(!d.device.empty());
        CHECK(d.tiles > 0); // 512 tiles: a device that took none never ran
    }
}

TEST_CASE("a device that cannot render is named, and bad tile sizes are refused", "[device][multi_device]")
{
    std::vector<Device> devices = cpu_devices();
    Scene scene = mixed_scene();
    std::vector<Device> with_empty = {devices[0], Device()};
    REQUIRE_THROWS_WITH(MultiDeviceRenderer(with_empty, scene), Catch::Contains("device 1 (empty Device)"));
    REQUIRE_THROWS_AS(MultiDeviceRenderer(std::vector<Device>{}, scene), Error);
    MultiDeviceRenderer many(devices, scene);
    Camera camera = Camera::framing(scene.bounds());
    for (int tile : {0, -3, 5000}) {
        MultiDeviceOptions o;
        o.tile = tile;
        REQUIRE_THROWS_WITH(many.render(camera, 64, 64, Path::Raster, o), Catch::Contains("screen tile size"));
    }
    REQUIRE_THROWS_WITH(many.render(camera, 0, 64, Path::Raster), Catch::Contains("image size"));
    REQUIRE_THROWS_WITH(many.renderer(devices.size()), Catch::Contains("no device"));
}

// Two platforms in one frame: PoCL's CPU device and Mesa's Rusticl on llvmpipe (the CTest entry
// multi_device_mixed sets RUSTICL_ENABLE=llvmpipe where Mesa's ICD is installed). Rusticl has no
// 64-bit atomics: its raster tiles are drawn by tile ownership, with the same keys.
TEST_CASE("a CPU device and another platform's device draw one frame together", "[.mixed_platforms]")
{
    std::vector<Device> devices;
    for (const DeviceInfo& info : list_devices())
        if (info.platform.find("Portable") == 0 || info.platform == "rusticl")
            devices.push_back(Device::open(std::to_string(info.index)));
    REQUIRE(devices.size() == 2);
    REQUIRE(devices[0].info().platform != devices[1].info().platform);
    Scene scene = mixed_scene();
    Camera camera = Camera::framing(scene.bounds());
    MultiDeviceOptions o;
    o.tile = 16;
    MultiDeviceRenderer many(devices, scene);
    std::vector<std::uint64_t> want = Renderer(devices[0], scene).render(camera, 61, 37, Path::Ray).read_keys();
    MultiDeviceFrame f = many.render(camera, 61, 37, Path::Ray, o);
    CHECK(f.keys == want);
    std::size_t rusticl = devices[0].info().platform == "rusticl" ? 0 : 1;
    std::string name = devices[rusticl].info().name;
    CHECK(f.devices[rusticl].device == name);
    INFO("tiles drawn: " << f.devices[0].tiles << " and " << f.devices[1].tiles);
    CHECK(f.devices[0].tiles + f.devices[1].tiles == f.tiles);
    // The raster path too: tile ownership where a device lacks 64-bit atomics, the same keys.
    std::vector<std::uint64_t> want_raster = Renderer(devices[0], scene).render(camera, 61, 37, Path::Raster).read_keys();
    CHECK(many.render(camera, 61, 37, Path::Raster, o).keys == want_raster);
    // A device that fails inside the frame is named: the atomic depth test asked of a device
    // without 64-bit atomics (its raster pipeline is made on its first tile).
    RenderOptions atomics;
    atomics.raster_atomics = RasterAtomics::On;
    MultiDeviceRenderer strict(devices, scene, atomics);
    if (!devices[rusticl].info().int64_atomics)
        REQUIRE_THROWS_WITH(strict.render(camera, 61, 37, Path::Raster, o),
                            Catch::Contains("device " + std::to_string(rusticl) + " (" + name + "): ") &&
                                Catch::Contains("64-bit atomics"));
}
