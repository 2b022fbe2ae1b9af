// Which CPUs the process may run on, for placing worker threads one per CPU: PoCL's (through
// POCL_AFFINITY, device.cpp) and the bench's reference renderers' (bench/pinned_threads.cpp).
#pragma once

#include <vector>

namespace clvis::detail {

/// n when the CPUs in `allowed` are exactly 0 .. n-1 with n = `online` >= 2, else 0: thread i
/// may then be pinned to CPU i. taskset, cgroup cpusets and mpirun's core binding restrict the
/// mask (CPU i may lie outside it), and one CPU leaves nothing to place.
int owned_cpus(long online, const std::vector<int>& allowed);

/// owned_cpus of the calling thread's affinity mask and the online CPUs (0 off Linux).
int owned_cpus();

} // namespace clvis::detail
