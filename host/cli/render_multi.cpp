// clvis render --devices: opens each device, renders the frame on all of them (warm-up, then
// --repeat timed frames), writes the files of the last frame and reports each device's tiles and
// busy time (also as --json).
#include "render_multi.hpp"

#include "bench_stats.hpp"

#include <clvis/multi_device.hpp>
#include <clvis/views_file.hpp>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>

namespace clvis::cli {

std::vector<std::string> device_specs(const std::string& list)
{
    std::vector<std::string> specs;
    std::size_t start = 0;
    while (true) {
        std::size_t comma = list.find(',', start);
        std::string spec = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (spec.empty())
            throw Error(Error::Kind::InvalidArgument, "--devices: expected SPEC,SPEC,... without empty specs, got '" +
                                                          list + "'");
        specs.push_back(spec);
        if (comma == std::string::npos) return specs;
        start = comma + 1;
    }
}

namespace {

#if CLVIS_WITH_IMAGE_IO
/// The device that drew each pixel, one colour per device (up to eight, then repeating).
Image device_map_image(const MultiDeviceFrame& f)
{
    static const std::uint8_t palette[8][3] = {{230, 25, 75}, {60, 180, 75},  {0, 130, 200}, {245, 130, 48},
                                               {145, 30, 180}, {70, 240, 240}, {240, 50, 230}, {128, 128, 0}};
    Image img;
    img.width = f.width;
    img.height = f.height;
    img.rgba.resize(f.device_of.size() * 4);
    for (std::size_t i = 0; i < f.device_of.size(); ++i) {
        const std::uint8_t* c = palette[f.device_of[i] % 8];
        std::copy(c, c + 3, &img.rgba[4 * i]);
        img.rgba[4 * i + 3] = 255;
    }
    return img;
}
#endif

/// Writes the frame's files through the run's plan (temporaries, then renamed together).
void write_files(const SpreadRequest& r, const MultiDeviceFrame& f)
{
    const std::string& device_map = r.spread.device_map;
    if (r.ids.empty() && r.depth.empty() && device_map.empty()) return;
#if CLVIS_WITH_IMAGE_IO
    HostVisibility vis = split_keys(f.keys.data(), f.width, f.height, 1, f.layers);
    // One view: "{view}" in a name is 0, as render.cpp planned it.
    if (!r.ids.empty()) write_ids(r.plan->temporary(view_file_name(r.ids, 0, 0)), vis);
    if (!r.depth.empty()) write_depth(r.plan->temporary(view_file_name(r.depth, 0, 0)), vis);
    if (!device_map.empty()) write_image(r.plan->temporary(device_map), device_map_image(f));
    for (const std::string& file : r.plan->commit())
        if (!r.quiet) std::cerr << "clvis: wrote " << file << "\n";
#else
    (void)f;
    throw Error(Error::Kind::InvalidArgument, "--ids/--depth/--device-map: this clvis was built without OpenImageIO");
#endif
}

void report(const SpreadRequest& r, Path path, const std::vector<MultiDeviceFrame>& frames)
{
    std::vector<double> samples;
    for (const auto& f : frames) samples.push_back(f.frame_ms);
    const MultiDeviceFrame& best = *std::min_element(
        frames.begin(), frames.end(), [](const MultiDeviceFrame& a, const MultiDeviceFrame& b) { return a.frame_ms < b.frame_ms; });
    if (!r.quiet) {
        std::fprintf(stderr, "clvis: %zu devices, %s path, %d tiles of %d px: frame %.2f ms min, %.2f ms median\n",
                     best.devices.size(), to_string(path), best.tiles, r.spread.screen_tile, best.frame_ms,
                     bench::median_of(samples));
        for (std::size_t d = 0; d < best.devices.size(); ++d)
            std::fprintf(stderr, "clvis:   device %zu (%s): %d tiles, busy %.2f ms\n", d,
                         best.devices[d].device.c_str(), best.devices[d].tiles, best.devices[d].busy_ms);
    }
    if (!r.json) return;
    nlohmann::json devices = nlohmann::json::array();
    for (const auto& d : best.devices)
        devices.push_back({{"device", d.device}, {"tiles", d.tiles}, {"busy_ms", d.busy_ms}});
    nlohmann::json j{{"path", to_string(path)},
                     {"triangles", r.file->scene.triangle_count()},
                     {"width", r.width},
                     {"height", r.height},
                     {"screen_tile", r.spread.screen_tile},
                     {"tiles", best.tiles},
                     {"load_ms", r.load_ms},
                     {"frame_ms", {{"min", *std::min_element(samples.begin(), samples.end())},
                                   {"median", bench::median_of(samples)},
                                   {"samples", samples}}},
                     {"devices", devices},
                     {"camera", r.cameras.front().to_flags()}};
    std::cout << j.dump(2) << "\n";
}

} // namespace

void render_multi_device(const SpreadRequest& r, Path path)
{
    std::vector<Device> devices;
    for (const std::string& spec : device_specs(r.spread.devices)) devices.push_back(Device::open(spec));
    MultiDeviceRenderer renderer(devices, r.file->scene, r.options);
    renderer.prepare(path);
    MultiDeviceOptions o;
    o.tile = r.spread.screen_tile;
    o.device_map = !r.spread.device_map.empty();
    const Camera& camera = r.cameras.front();
    if (r.repeat > 0) renderer.render(camera, r.width, r.height, path, o); // warm-up: first launches compile
    std::vector<MultiDeviceFrame> frames;
    for (int i = 0; i < std::max(r.repeat, 1); ++i)
        frames.push_back(renderer.render(camera, r.width, r.height, path, o));
    write_files(r, frames.back());
    report(r, path, frames);
}

} // namespace clvis::cli
