// The machine a benchmark ran on and how busy it was: /proc/loadavg around every point and
// sweep, the online cores and the CPU model, written into bench.json and bench.csv so that a
// figure taken on a loaded machine says so.
#pragma once

#include <string>

namespace clvis::bench {

/// /proc/loadavg: run-queue averages over 1, 5 and 15 minutes; all -1 where it cannot be read.
struct Load {
    double one = -1, five = -1, fifteen = -1;
    bool known() const { return one >= 0; }
};
Load read_load();
/// "1.23 0.98 0.75", or "unknown".
std::string to_string(const Load& load);

struct Machine {
    int cores = 0;         ///< online processors (sysconf), what nproc prints
    std::string cpu_model; ///< /proc/cpuinfo's first "model name", or "unknown"
};
Machine read_machine();

} // namespace clvis::bench
