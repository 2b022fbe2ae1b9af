// run_pinned: see pinned_threads.hpp.
#include "pinned_threads.hpp"

#include "runtime/cpus.hpp"

#if defined(__linux__)
#include <pthread.h>
#include <sched.h>
#endif

namespace clvis::bench {

namespace {

#if defined(__linux__)
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
    int n = detail::owned_cpus();
#if defined(__linux__)
    cpu_set_t saved;
    if (n && pthread_getaffinity_np(pthread_self(), sizeof saved, &saved) != 0) n = 0;
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
