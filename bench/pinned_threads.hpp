// The reference renderers' tracing threads, one per CPU. clvis pins PoCL's workers (worker i on
// CPU i; host/runtime/device.cpp, pin_pocl_workers). Left unpinned, the references' threads met
// the scheduler trap that had slowed PoCL's: the std::thread started for a frame was often placed
// on the core of the thread that started it and stayed there for the frame, so Embree's
// rtcIntersect16 frames took 2.5 or 3.6-3.9 ms (bunny 640x480) pass by pass. The same rule
// decides (runtime/cpus.hpp, owned_cpus): pinned only where the process may run on every online
// CPU, 0 to n-1.
#pragma once

#include <functional>
#include <thread>
#include <vector>

namespace clvis::bench {

/// Runs `worker` on `threads` threads: the caller's and threads - 1 std::threads, thread k on CPU
/// k mod n where the process may run on every online CPU (the caller's own mask restored after),
/// else unpinned.
void run_pinned(int threads, const std::function<void()>& worker);

} // namespace clvis::bench
