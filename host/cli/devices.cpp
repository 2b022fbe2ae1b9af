// clvis devices: what OpenCL devices are there, and what they offer that clvis needs.
#include "commands.hpp"

#include <clvis/clvis.hpp>

#include <cstdio>
#include <string>
#include <iostream>

namespace clvis::cli {

namespace {

/// A cached choice (RasterMapping::Auto): "tuned  raster_mapping pixel (depth_test owned, tile 16;
/// square 3.1 ms, pixel 1.2 ms)"; the kernels' hash and the workload are left out.
void print_tuned(const TunedChoice& c)
{
    std::string detail;
    for (const auto& [field, value] : c.key)
        if (field != "kernels" && field != "workload") detail += (detail.empty() ? "" : ", ") + field + " " + value;
    char ms[64];
    for (std::size_t i = 0; i < c.times_ms.size(); ++i) {
        std::snprintf(ms, sizeof ms, "%s%s %.3g ms", i == 0 ? "; " : ", ", c.times_ms[i].first.c_str(),
                      c.times_ms[i].second);
        detail += ms;
    }
    std::printf("    tuned           %s %s (%s)\n", c.name.c_str(), c.choice.c_str(), detail.c_str());
}

} // namespace

void add_devices_command(CLI::App& app)
{
    auto* cmd = app.add_subcommand("devices", "List the OpenCL devices (the index is what --device takes).\n"
                                              "Example: clvis devices");
    cmd->callback([] {
        auto devices = list_devices();
        Device chosen = Device::open();
        for (const auto& d : devices) {
            bool is_default = d.index == chosen.info().index; // two alike devices share a name
            std::printf("%zu%s %s\n", d.index, is_default ? "*" : " ", d.name.c_str());
            std::printf("    platform        %s\n", d.platform.c_str());
            std::printf("    type            %s, %u compute units\n", to_string(d.type), d.compute_units);
            std::printf("    memory          %.0f MiB global, %.0f MiB largest buffer, %.0f KiB local\n",
                        d.global_memory / 1048576.0, d.max_allocation / 1048576.0, d.local_memory / 1024.0);
            std::printf("    version         %s; driver %s; %s\n", d.version.c_str(), d.driver_version.c_str(),
                        d.opencl_c_version.c_str());
            std::printf("    64-bit atomics  %s\n", d.int64_atomics ? "yes (the raster path's atomic depth test)"
                                                             : "no (the raster path uses tile ownership)");
            std::printf("    fp64            %s\n", d.fp64 ? "yes" : "no");
            for (const TunedChoice& c : tuned_choices(d)) print_tuned(c);
        }
        std::printf("* the device clvis picks by default%s\n",
                    std::getenv("CLVIS_DEVICE") ? " (CLVIS_DEVICE is set)" : " (first GPU, else first CPU)");
    });
}

} // namespace clvis::cli
