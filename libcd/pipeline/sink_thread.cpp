#include "libcd/pipeline/sink_thread.hpp"

#include <algorithm>

namespace snag {

SinkThread::SinkThread(ScanSink& sink, std::size_t capacity)
    : sink_(sink), capacity_(std::max<std::size_t>(capacity, 1)), lanes_(std::min(sink.lanes(), capacity_)) {
  for (std::size_t arena = 0; arena <= lanes_; ++arena) arenas_.push_back(std::make_unique<tbb::task_arena>());
  for (std::size_t lane = 0; lane < lanes_; ++lane) lane_threads_.emplace_back([this, lane] { run_lane(lane); });
  thread_ = std::thread([this] { run_frames(); });
}

SinkThread::~SinkThread() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;  // the frames in prepare() or frame() are finished first
  }
  changed_.notify_all();
  thread_.join();
  for (std::thread& lane : lane_threads_) lane.join();
}

template <class Work>
std::exception_ptr SinkThread::in_arena(tbb::task_arena& arena, Work work) {
  try {
    arena.execute(work);
  } catch (...) {
    return std::current_exception();
  }
  return nullptr;
}

void SinkThread::start_work_locked() {
  if (working_++ == 0) busy_since_ = Clock::now();
}

void SinkThread::end_work_locked() {
  if (--working_ == 0) sink_seconds_ += std::chrono::duration<double>(Clock::now() - busy_since_).count();
}

void SinkThread::run_frames() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock,
                  [&] { return stopping_ || error_ || (!held_.empty() && held_.front().stage == Stage::kPrepared); });
    if (stopping_ || error_) return;
    Held& held = held_.front();  // stays put: the deque only grows at the back meanwhile
    held.stage = Stage::kInFrame;
    start_work_locked();
    lock.unlock();
    const std::exception_ptr error = in_arena(*arenas_[lanes_], [&] { sink_.frame(held.frame); });
    lock.lock();
    end_work_locked();
    held_.pop_front();
    if (error && !error_) error_ = error;  // no frame after a failed one
    changed_.notify_all();
  }
}

void SinkThread::run_lane(std::size_t lane) {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    Held* next = nullptr;
    changed_.wait(lock, [&] {
      if (stopping_ || error_) return true;
      // The lane's earliest frame held, once the one before it on the lane
      // is through frame() (popped): its digest is free again.
      for (Held& held : held_) {
        if (held.frame.lane != lane) continue;
        if (held.stage != Stage::kQueued) return false;
        next = &held;
        return true;
      }
      return false;
    });
    if (stopping_ || error_) return;
    next->stage = Stage::kPreparing;  // not taken off the deque before frame() is done with it
    start_work_locked();
    lock.unlock();
    const std::exception_ptr error = in_arena(*arenas_[lane], [&] { sink_.prepare(next->frame); });
    lock.lock();
    end_work_locked();
    next->stage = Stage::kPrepared;
    if (error && !error_) error_ = error;
    changed_.notify_all();
  }
}

void SinkThread::wait_locked(std::unique_lock<std::mutex>& lock, std::size_t frames) {
  const auto start = Clock::now();
  changed_.wait(lock, [&] { return error_ || held_.size() <= frames; });
  wait_seconds_ += std::chrono::duration<double>(Clock::now() - start).count();
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
    held_.push_back({frame, lanes_ == 0 ? Stage::kPrepared : Stage::kQueued});
    held_.back().frame.lane = lanes_ == 0 ? 0 : handed_ % lanes_;
    ++handed_;
  }
  changed_.notify_all();
}

double SinkThread::sink_seconds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sink_seconds_;
}

}  // namespace snag
