// The process's worker threads (thread_pool.hpp): one queue under one mutex, workers taking the
// oldest task, waiting callers the newest (most likely their own, the smallest). A thread that
// finds nothing to do polls for a short while (spin_for) before it sleeps, and threads are woken
// only when one sleeps: a build hands out tasks in bursts, and waking a sleeping thread costs tens
// of microseconds (on a VM, an interrupt through the host), which a build of a few thousand
// triangles, under a millisecond, paid at every task.
#include "runtime/thread_pool.hpp"

#include <clvis/error.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <new>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace clvis::detail {

class ThreadPool {
public:
    static ThreadPool& get()
    {
        static ThreadPool pool;
        return pool;
    }

    unsigned workers() const { return unsigned(threads_.size()); }

    void push(TaskGroup& group, std::function<void()> fn)
    {
        bool wake;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            queue_.push_back({&group, std::move(fn)});
            queued_.store(queue_.size());
            wake = sleepers_ > 0;
        }
        if (wake) cv_.notify_one();
    }

    /// Runs queued tasks until `group` has none unfinished.
    void wait_for(TaskGroup& group)
    {
        std::unique_lock<std::mutex> lock(mutex_);
        while (group.pending_.load() > 0) {
            if (queue_.empty()) {
                idle(lock, [&] { return group.pending_.load() == 0 || queued_.load() > 0; });
                continue;
            }
            Task task = std::move(queue_.back());
            queue_.pop_back();
            queued_.store(queue_.size());
            execute(task, lock);
        }
    }

    static void run_task(TaskGroup& group, const std::function<void()>& fn)
    {
        std::exception_ptr error;
        try {
            fn();
        } catch (...) {
            error = std::current_exception();
        }
        group.finish(error);
    }

private:
    struct Task {
        TaskGroup* group;
        std::function<void()> fn;
    };

    ThreadPool()
    {
        unsigned hw = std::thread::hardware_concurrency();
        unsigned n = hw <= 1 ? 0 : hw - 1;
        for (unsigned i = 0; i < n; ++i) threads_.emplace_back([this] { work(); });
    }
    ~ThreadPool()
    {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_.store(true);
        }
        cv_.notify_all();
        for (std::thread& t : threads_) t.join();
    }

    /// Runs `task` with the lock released, then wakes every sleeper (one may wait for its group).
    void execute(Task& task, std::unique_lock<std::mutex>& lock)
    {
        lock.unlock();
        run_task(*task.group, task.fn);
        task.fn = nullptr; // the task's captures go before its group is seen as done
        lock.lock();
        task.group->pending_.fetch_sub(1);
        if (sleepers_ > 0) cv_.notify_all();
    }

    /// Returns (holding the lock) once `ready` may hold: polls it without the lock for up to
    /// spin_for, then sleeps until woken. `ready` reads atomics only, so it may run unlocked; it
    /// is read again under the lock before sleeping, and every change it waits for is made under
    /// the lock, which then wakes the sleepers: no wake-up is lost.
    template <class Ready> void idle(std::unique_lock<std::mutex>& lock, Ready ready)
    {
        lock.unlock();
        auto until = std::chrono::steady_clock::now() + spin_for;
        bool done = false;
        for (int k = 0; !done; ++k) {
            done = ready();
            if (!done && (k & 63) == 63 && std::chrono::steady_clock::now() >= until) break;
#if defined(__x86_64__) || defined(__i386__)
            __builtin_ia32_pause();
#endif
        }
        lock.lock();
        if (done || ready()) return;
        ++sleepers_;
        cv_.wait(lock);
        --sleepers_;
    }

    void work()
    {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            if (stop_) return;
            if (queue_.empty()) {
                idle(lock, [this] { return stop_.load() || queued_.load() > 0; });
                continue;
            }
            Task task = std::move(queue_.front());
            queue_.pop_front();
            queued_.store(queue_.size());
            execute(task, lock);
        }
    }

    /// How long an idle thread polls before it sleeps: a build's next task comes within it.
    static constexpr std::chrono::microseconds spin_for{100};

    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Task> queue_;
    std::atomic<std::size_t> queued_{0}; ///< queue_.size(), for the unlocked polls
    unsigned sleepers_ = 0;              ///< threads in cv_.wait (under mutex_)
    std::atomic<bool> stop_{false};      ///< set under mutex_, also read by the unlocked polls
    std::vector<std::thread> threads_;
};

TaskGroup::~TaskGroup() { ThreadPool::get().wait_for(*this); }

void TaskGroup::run(std::function<void()> task)
{
    ThreadPool& pool = ThreadPool::get();
    if (pool.workers() == 0) {
        ThreadPool::run_task(*this, task);
        return;
    }
    pending_.fetch_add(1);
    pool.push(*this, std::move(task));
}

void TaskGroup::finish(std::exception_ptr error)
{
    if (!error) return;
    std::lock_guard<std::mutex> lock(error_mutex_);
    if (!error_) error_ = error;
}

void TaskGroup::wait()
{
    ThreadPool::get().wait_for(*this);
    std::exception_ptr error;
    {
        std::lock_guard<std::mutex> lock(error_mutex_);
        error = std::exchange(error_, nullptr);
    }
    if (!error) return;
    try {
        std::rethrow_exception(error);
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        throw Error(Error::Kind::Limit, "a worker task (thread pool) ran out of memory");
    } catch (const std::exception& e) {
        throw Error(Error::Kind::Limit, std::string("a worker task (thread pool) failed: ") + e.what());
    } catch (...) {
        throw Error(Error::Kind::Limit, "a worker task (thread pool) failed with an unknown exception");
    }
}

unsigned pool_workers() { return ThreadPool::get().workers(); }

void parallel_slices(std::size_t n, unsigned parts, const std::function<void(unsigned, std::size_t, std::size_t)>& body)
{
    parts = unsigned(std::max<std::size_t>(1, std::min<std::size_t>(parts, n)));
    TaskGroup group;
    for (unsigned t = 1; t < parts; ++t) {
        std::size_t b = n * t / parts, e = n * (t + 1) / parts;
        group.run([&body, t, b, e] { body(t, b, e); });
    }
    ThreadPool::run_task(group, [&body, n, parts] { body(0, 0, n / parts); });
    group.wait();
}

} // namespace clvis::detail
