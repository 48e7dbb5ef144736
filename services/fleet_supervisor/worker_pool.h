// A fixed number of worker threads with a bounded queue: a job that finds the queue full is not
// taken (the caller answers "busy" at once) instead of waiting behind an unbounded backlog.
// Jobs still queued at Stop() are handed to `drop` (to release what they hold).
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace fleetloc::fleet_supervisor {

template <typename Job>
class WorkerPool {
 public:
  WorkerPool(int threads, size_t capacity, std::function<void(Job&)> work,
             std::function<void(Job&)> drop)
      : capacity_(capacity), work_(std::move(work)), drop_(std::move(drop)) {
    for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { Run(); });
  }
  ~WorkerPool() { Stop(); }
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  // Queues `job`; false (job untouched) when `capacity` jobs already wait or the pool stopped.
  bool TryPush(Job& job) {
    {
      std::lock_guard lock(mutex_);
      if (stopping_ || queue_.size() >= capacity_) return false;
      queue_.push_back(std::move(job));
    }
    wake_.notify_one();
    return true;
  }

  // Lets the running jobs finish, drops the queued ones, joins the threads. Idempotent.
  void Stop() {
    std::deque<Job> left;
    {
      std::lock_guard lock(mutex_);
      if (stopping_) return;
      stopping_ = true;
      left.swap(queue_);
    }
    wake_.notify_all();
    for (Job& job : left) drop_(job);
    for (std::thread& t : threads_) t.join();
  }

 private:
  void Run() {
    for (;;) {
      Job job;
      {
        std::unique_lock lock(mutex_);
        wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (queue_.empty()) return;  // stopping
        job = std::move(queue_.front());
        queue_.pop_front();
      }
      work_(job);
    }
  }

  const size_t capacity_;
  std::function<void(Job&)> work_, drop_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Job> queue_;
  bool stopping_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace fleetloc::fleet_supervisor
