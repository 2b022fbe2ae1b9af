// owned_cpus: see cpus.hpp.
#include "runtime/cpus.hpp"

#include <algorithm>

#if defined(__linux__)
#include <sched.h>
#include <unistd.h>
#endif

namespace clvis::detail {

int owned_cpus(long online, const std::vector<int>& allowed)
{
    if (online < 2 || long(allowed.size()) != online) return 0;
    std::vector<int> sorted = allowed;
    std::sort(sorted.begin(), sorted.end());
    for (long cpu = 0; cpu < online; ++cpu)
        if (sorted[std::size_t(cpu)] != cpu) return 0;
    return int(online);
}

int owned_cpus()
{
#if defined(__linux__)
    cpu_set_t mask;
    CPU_ZERO(&mask);
    if (sched_getaffinity(0, sizeof mask, &mask) != 0) return 0;
    std::vector<int> allowed;
    for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu)
        if (CPU_ISSET(cpu, &mask)) allowed.push_back(cpu);
    return owned_cpus(sysconf(_SC_NPROCESSORS_ONLN), allowed);
#else
    return 0;
#endif
}

} // namespace clvis::detail
