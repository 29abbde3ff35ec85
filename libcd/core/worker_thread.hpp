// Threads kept for their owner's life, so that work handed on every frame or
// step starts no thread each time: a queue of tasks run in order
// (TaskQueueThread), and a worker whose tasks answer through futures
// (WorkerThread).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>

namespace snag {

/// A thread that runs the tasks handed to it one after another, in the order
/// they were handed, while the thread that hands them goes on: copies a
/// later step needs done, but not now, kept in order.
class TaskQueueThread {
 public:
  TaskQueueThread() : thread_([this] { loop(); }) {}
  /// Runs the tasks still queued, then ends the thread.
  ~TaskQueueThread() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  TaskQueueThread(const TaskQueueThread&) = delete;
  TaskQueueThread& operator=(const TaskQueueThread&) = delete;

  /// Queues `task` after those handed before it; returns its ticket for
  /// wait_for (tickets count up from 1).
  std::uint64_t post(std::function<void()> task) {
    std::uint64_t ticket = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      queue_.push_back(std::move(task));
      ticket = ++posted_;
    }
    wake_.notify_all();
    return ticket;
  }

  /// Waits till the task of `ticket` and those before it have run; rethrows
  /// the first that threw since the last wait (the tasks after it were
  /// dropped).
  void wait_for(std::uint64_t ticket) {
    std::unique_lock<std::mutex> lock(mutex_);
    wake_.wait(lock, [&] { return done_ >= ticket; });
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
  }
  /// Waits till the tasks handed so far have run; rethrows as wait_for.
  void wait() {
    std::uint64_t last = 0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      last = posted_;
    }
    wait_for(last);
  }

 private:
  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopped
      std::function<void()> task = std::move(queue_.front());
      queue_.pop_front();
      lock.unlock();
      std::exception_ptr error;
      try {
        task();
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      ++done_;
      if (error) {
        if (!error_) error_ = error;
        queue_.clear();  // what follows a failed task is not run: its order is lost
        done_ = posted_;
      }
      wake_.notify_all();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;  ///< a task was queued, one ran, or stop
  std::deque<std::function<void()>> queue_;
  std::uint64_t posted_ = 0;  ///< tasks handed so far
  std::uint64_t done_ = 0;    ///< tasks run (or dropped after an error) so far
  bool stop_ = false;
  std::exception_ptr error_;  ///< the first task that threw since the last wait
  std::thread thread_;        ///< last: it starts once the members above are
};

/// A thread that runs one task at a time, kept for its owner's life: work
/// handed on every frame or step without starting a thread each time.
class WorkerThread {
 public:
  /// Runs `task` on the thread, after the tasks handed before it; the future
  /// holds what it threw. The thread finishes what it was handed before the
  /// worker goes.
  std::future<void> run(std::function<void()> task) {
    auto packaged = std::make_shared<std::packaged_task<void()>>(std::move(task));
    std::future<void> done = packaged->get_future();
    queue_.post([packaged] { (*packaged)(); });  // its error goes to the future, not to the queue
    return done;
  }

 private:
  TaskQueueThread queue_;
};

}  // namespace snag
