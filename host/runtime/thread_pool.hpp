// The process's one pool of worker threads, started on first use and sized by the machine's
// hardware threads, for host work split into tasks (the BVH build, host/ray/bvh_build.cpp): no
// thread is created per build or per task. Safe for any number of callers at once.
#pragma once

#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>

namespace clvis::detail {

/// Tasks run on the pool and waited for together. wait() runs queued tasks (its own or others')
/// on the calling thread while its own are unfinished, so tasks may wait on groups of their own
/// without tying up the pool. The first exception a task throws reaches the caller of wait() as a
/// clvis::Error (an Error as it was thrown); the group's other tasks still run to their end.
class TaskGroup {
public:
    TaskGroup() = default;
    TaskGroup(const TaskGroup&) = delete;
    TaskGroup& operator=(const TaskGroup&) = delete;
    /// Waits for the group's tasks (an exception they threw is dropped here: call wait()).
    ~TaskGroup();

    /// Queues `task`; with no worker threads (a 1-thread machine) it runs at once.
    void run(std::function<void()> task);
    /// Returns when every task run() queued has finished; throws the first one's exception.
    void wait();

private:
    friend class ThreadPool;
    void finish(std::exception_ptr error);

    std::atomic<std::size_t> pending_{0};
    std::mutex error_mutex_;
    std::exception_ptr error_;
};

/// Worker threads in the pool: the machine's hardware threads less one (the waiting caller
/// works too), at least 1; 0 where the machine reports a single hardware thread.
unsigned pool_workers();

/// Runs body(part, b, e) on `parts` contiguous, near-equal slices [b, e) of [0, n) (part 0 first),
/// the first on the calling thread and the rest on the pool; returns when all are done. The first
/// exception a slice throws reaches the caller as TaskGroup::wait() hands it on.
void parallel_slices(std::size_t n, unsigned parts, const std::function<void(unsigned, std::size_t, std::size_t)>& body);

} // namespace clvis::detail
