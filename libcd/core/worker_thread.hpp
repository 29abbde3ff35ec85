// A thread that runs one task at a time, kept for its owner's life: work
// handed on every frame or step without starting a thread each time.
#pragma once

#include <condition_variable>
#include <functional>
#include <future>
#include <mutex>
#include <thread>
#include <utility>

namespace snag {

class WorkerThread {
 public:
  WorkerThread() : thread_([this] { loop(); }) {}
  /// Finishes the task it runs, if any, and ends the thread.
  ~WorkerThread() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
  }
  WorkerThread(const WorkerThread&) = delete;
  WorkerThread& operator=(const WorkerThread&) = delete;

  /// Runs `task` on the thread; the future holds what it threw. The future
  /// of the previous task must have been waited for.
  std::future<void> run(std::function<void()> task) {
    std::packaged_task<void()> packaged(std::move(task));
    std::future<void> done = packaged.get_future();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      task_ = std::move(packaged);
    }
    wake_.notify_one();
    return done;
  }

 private:
  void loop() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return stop_ || task_.valid(); });
      if (!task_.valid()) return;  // stopped
      std::packaged_task<void()> task = std::move(task_);
      lock.unlock();
      task();
      lock.lock();
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::packaged_task<void()> task_;  ///< valid while a task waits for the thread
  bool stop_ = false;
  std::thread thread_;  ///< last: it starts once the members above are
};

}  // namespace snag
