// run_pinned: see pinned_threads.hpp.
#include "pinned_threads.hpp"

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#include <unistd.h>
#endif

namespace clvis::bench {

namespace {

#if defined(__linux__)
/// The CPUs 0 .. n-1 when the process may run on every online CPU (n of them), else 0.
int all_cpus(cpu_set_t& mask)
{
    long online = sysconf(_SC_NPROCESSORS_ONLN);
    CPU_ZERO(&mask);
    if (online < 2 || online > CPU_SETSIZE || pthread_getaffinity_np(pthread_self(), sizeof mask, &mask) != 0)
        return 0;
    if (CPU_COUNT(&mask) != online) return 0;
    for (long cpu = 0; cpu < online; ++cpu)
        if (!CPU_ISSET(int(cpu), &mask)) return 0;
    return int(online);
}

void pin(pthread_t thread, int cpu)
{
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    pthread_setaffinity_np(thread, sizeof one, &one); // a hint: a failure leaves it unpinned
}
#endif

} // namespace

void run_pinned(int threads, const std::function<void()>& worker)
{
#if defined(__linux__)
    cpu_set_t saved;
    int n = all_cpus(saved);
#else
    int n = 0;
#endif
    std::vector<std::thread> pool;
    for (int k = 1; k < threads; ++k) {
        pool.emplace_back(worker);
#if defined(__linux__)
        if (n) pin(pool.back().native_handle(), k % n);
#endif
    }
#if defined(__linux__)
    if (n) pin(pthread_self(), 0);
#endif
    worker();
#if defined(__linux__)
    if (n) pthread_setaffinity_np(pthread_self(), sizeof saved, &saved);
#endif
    for (auto& th : pool) th.join();
}

} // namespace clvis::bench
