#include "libcd/pipeline/sink_thread.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

namespace snag {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

SinkThread::SinkThread(ScanSink& sink, std::size_t capacity, std::function<void(ScannedFrame&)> finish)
    : sink_(sink),
      capacity_(std::max<std::size_t>(capacity, 1)),
      finish_(std::move(finish)),
      thread_([this] { run(); }) {}

SinkThread::~SinkThread() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    queue_.clear();  // the frame in the sink, if any, is finished first
  }
  changed_.notify_all();
  thread_.join();
}

void SinkThread::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
    if (stopping_) return;
    ScannedFrame frame = queue_.front();
    queue_.pop_front();
    in_sink_ = true;
    lock.unlock();
    const auto start = Clock::now();
    std::exception_ptr error;
    try {
      arena_.execute([&] {
        if (finish_) finish_(frame);
        sink_.frame(frame);
      });
    } catch (...) {
      error = std::current_exception();
    }
    const double seconds = seconds_since(start);
    lock.lock();
    sink_seconds_ += seconds;
    in_sink_ = false;
    if (error) {
      error_ = error;
      queue_.clear();  // no frame after a failed one
    }
    changed_.notify_all();
  }
}

void SinkThread::wait_locked(std::unique_lock<std::mutex>& lock, std::size_t frames) {
  const auto start = Clock::now();
  changed_.wait(lock, [&] { return error_ || queue_.size() + in_sink_ <= frames; });
  wait_seconds_ += seconds_since(start);
  if (error_) std::rethrow_exception(error_);
}

void SinkThread::wait_until_at_most(std::size_t frames) {
  std::unique_lock<std::mutex> lock(mutex_);
  wait_locked(lock, frames);
}

void SinkThread::hand(const ScannedFrame& frame) {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    wait_locked(lock, capacity_ - 1);
    queue_.push_back(frame);
  }
  changed_.notify_all();
}

double SinkThread::sink_seconds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sink_seconds_;
}

}  // namespace snag
