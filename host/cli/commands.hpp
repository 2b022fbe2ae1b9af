// The subcommands of the clvis tool, one file each; main.cpp registers them and maps every
// failure to one of the exit statuses below.
#pragma once

#include <CLI/CLI.hpp>

namespace clvis::cli {

/// Exit statuses of every subcommand.
constexpr int exit_ok = 0;       ///< done (and the referee, where it judged, rejected nothing)
constexpr int exit_rejected = 1; ///< done, and the referee rejected answers (render --path all, compare)
constexpr int exit_usage = 2;    ///< nothing done: bad flags or values, unusable files, no device

/// Prints a flag-parsing error as one line "clvis: ..." naming the flag (or the help, for
/// --help) and returns the exit status: exit_usage, or 0 for --help and --version.
int report_parse_error(const CLI::App& app, const CLI::ParseError& error);

void add_devices_command(CLI::App& app);
void add_info_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_bench_command(CLI::App& app);
void add_rays_command(CLI::App& app);

/// Blocks of 1 MB or more mapped on their own and returned to the system when freed (glibc; a
/// no-op elsewhere): what render and rays set before loading (memory_policy.cpp, issue 37).
void return_large_blocks();

} // namespace clvis::cli
