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
    : sink_(sink), capacity_(std::max<std::size_t>(capacity, 1)), finish_(std::move(finish)) {
  const std::size_t threads = std::clamp<std::size_t>(sink_.frames_at_once(), 1, capacity_);
  for (std::size_t t = 0; t < threads; ++t) threads_.emplace_back([this] { run(); });
}

SinkThread::~SinkThread() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    queue_.clear();  // the frames in the sink, if any, are finished first
  }
  changed_.notify_all();
  for (std::thread& thread : threads_) thread.join();
}

void SinkThread::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
    if (stopping_) return;
    ScannedFrame frame = queue_.front();
    queue_.pop_front();
    const std::size_t ticket = next_ticket_++;
    if (in_sink_++ == 0) busy_since_ = Clock::now();
    lock.unlock();
    // Prepared beside the other threads' frames; then, in turn, into the
    // sink, unless a frame before it failed or the scan is going.
    std::exception_ptr error;
    try {
      arena_.execute([&] {
        if (finish_) finish_(frame);
        sink_.prepare(frame);
      });
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    changed_.wait(lock, [&] { return turn_ == ticket; });
    if (!error && !error_ && !stopping_) {
      lock.unlock();
      try {
        arena_.execute([&] { sink_.frame(frame); });
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
    }
    ++turn_;
    if (--in_sink_ == 0) sink_seconds_ += seconds_since(busy_since_);
    if (error && !error_) {
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
  return sink_seconds_ + (in_sink_ > 0 ? seconds_since(busy_since_) : 0.0);
}

}  // namespace snag
