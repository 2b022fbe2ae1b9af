// The subcommands of the clvis tool, one file each; main.cpp registers them.
#pragma once

#include <CLI/CLI.hpp>

namespace clvis::cli {

void add_devices_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_rays_command(CLI::App& app);

} // namespace clvis::cli
