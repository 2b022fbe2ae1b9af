// The process's worker threads (thread_pool.hpp): one queue under one mutex, workers taking the
// oldest task, waiting callers the newest (most likely their own, the smallest).
#include "runtime/thread_pool.hpp"

#include <clvis/error.hpp>

#include <algorithm>
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
        {
            std::lock_guard<std::mutex> lock(mutex_);
            queue_.push_back({&group, std::move(fn)});
        }
        cv_.notify_one();
    }

    /// Runs queued tasks until `group` has none unfinished.
    void wait_for(TaskGroup& group)
    {
        std::unique_lock<std::mutex> lock(mutex_);
        while (group.pending_.load() > 0) {
            if (queue_.empty()) {
                cv_.wait(lock);
                continue;
            }
            Task task = std::move(queue_.back());
            queue_.pop_back();
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
            stop_ = true;
        }
        cv_.notify_all();
        for (std::thread& t : threads_) t.join();
    }

    /// Runs `task` with the lock released, then wakes every waiter (one may wait for its group).
    void execute(Task& task, std::unique_lock<std::mutex>& lock)
    {
        lock.unlock();
        run_task(*task.group, task.fn);
        task.fn = nullptr; // the task's captures go before its group is seen as done
        lock.lock();
        task.group->pending_.fetch_sub(1);
        cv_.notify_all();
    }

    void work()
    {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            cv_.wait(lock, [this] { return stop_ || !queue_.empty(); });
            if (queue_.empty()) return; // stop_
            Task task = std::move(queue_.front());
            queue_.pop_front();
            execute(task, lock);
        }
    }

    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Task> queue_;
    bool stop_ = false;
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
