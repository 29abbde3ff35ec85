// One thread for the scan's sink, for the whole scan: frames are handed to it
// through a bounded queue and it calls ScanSink::frame on them in order, so
// that the report of frame f is written while the scan goes on with the next
// ones and no thread is started per frame. A sink with lanes
// (ScanSink::lanes) also gets ScanSink::prepare for each frame, ahead of
// frame(), on a thread per lane: the frames held are prepared at once, each
// on its own lane, while the earliest of them is in frame().
#pragma once

#include <tbb/task_arena.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "libcd/pipeline/scan.hpp"

namespace snag {

class SinkThread {
 public:
  /// Starts the threads. `capacity` (at least 1): how many frames may wait or
  /// be in the sink at once; the scan's buffers must outlive them. The sink
  /// gets min(sink.lanes(), capacity) lanes, frame i going to lane i % lanes;
  /// a lane prepares its next frame once frame() is done with its last one.
  SinkThread(ScanSink& sink, std::size_t capacity);
  /// Drops the frames not yet started, waits for those in the sink and ends
  /// the threads (so that nothing uses the scan's buffers after it).
  ~SinkThread();
  SinkThread(const SinkThread&) = delete;
  SinkThread& operator=(const SinkThread&) = delete;

  /// Queues `frame`, first waiting while the queue is full. Rethrows what the
  /// sink threw on an earlier frame (after which it takes no more frames).
  void hand(const ScannedFrame& frame);
  /// Waits until at most `frames` frames are queued or in the sink. Rethrows
  /// what the sink threw.
  void wait_until_at_most(std::size_t frames);
  /// Waits for every frame handed over. Rethrows what the sink threw.
  void drain() { wait_until_at_most(0); }

  /// Time during which the sink worked on at least one frame (in prepare()
  /// or frame()), and time spent waiting in hand() and drain(), seconds, so
  /// far.
  double sink_seconds() const;
  double wait_seconds() const { return wait_seconds_; }

 private:
  using Clock = std::chrono::steady_clock;
  enum class Stage { kQueued, kPreparing, kPrepared, kInFrame };
  struct Held {
    ScannedFrame frame;
    Stage stage;
  };

  void run_frames();
  void run_lane(std::size_t lane);
  /// Runs `work` in `arena`; what it throws is returned.
  template <class Work>
  std::exception_ptr in_arena(tbb::task_arena& arena, Work work);
  void wait_locked(std::unique_lock<std::mutex>& lock, std::size_t frames);
  void start_work_locked();
  void end_work_locked();

  ScanSink& sink_;
  const std::size_t capacity_;
  const std::size_t lanes_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Held> held_;   // frames handed and not yet through frame(), in order
  std::size_t handed_ = 0;  // frames handed so far: the next one goes to lane handed_ % lanes_
  bool stopping_ = false;
  std::exception_ptr error_;
  std::size_t working_ = 0;  // frames in prepare() or frame() now
  Clock::time_point busy_since_;
  double sink_seconds_ = 0;  // under mutex_
  double wait_seconds_ = 0;  // the scan's thread only
  // The sink's parallel work runs in arenas of its own, one per thread
  // (lanes_ for the lanes, the last for frame()): a thread of the scan
  // waiting for its own tasks never picks up the sink's, and the sink's
  // threads never pick up the back end's (whose tasks can be long), so that
  // neither waits for the other's work; and each of the sink's threads has a
  // slot of its own to enter (in one arena of as many slots as cores, a
  // thread finding them all taken hands its work over for another thread
  // there to run, in among that thread's own).
  std::vector<std::unique_ptr<tbb::task_arena>> arenas_;
  std::vector<std::thread> lane_threads_;  // started once everything above is set up
  std::thread thread_;
};

}  // namespace snag
