// Threads for the scan's sink, for the whole scan: frames are handed to them
// through a bounded queue and they call ScanSink::frame on them in order, so
// that the report of frame f is written while the scan goes on with the next
// ones and no thread is started per frame. One thread, or as many as the
// sink prepares frames at once (ScanSink::frames_at_once, at most the
// queue's capacity): each takes the next frame, prepares it beside the
// others, and waits for the frames before it to leave the sink before it
// hands its own to ScanSink::frame.
#pragma once

#include <tbb/task_arena.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "libcd/pipeline/scan.hpp"

namespace snag {

class SinkThread {
 public:
  /// Starts the threads. `capacity` (at least 1): how many frames may wait or
  /// be in the sink at once; the scan's buffers must outlive them. `finish`,
  /// when set, is called on each frame on a sink's thread just before the
  /// sink's prepare() (the scan's last work on a frame, taken off the scan's
  /// thread).
  SinkThread(ScanSink& sink, std::size_t capacity, std::function<void(ScannedFrame&)> finish = {});
  /// Drops the frames not yet started, waits for the ones in the sink (those
  /// prepared and not yet in ScanSink::frame go no further) and ends the
  /// threads (so that nothing uses the scan's buffers after them).
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

  /// Time during which a frame was in the sink (in `finish`, prepare() or
  /// frame(), or waiting for its turn), and time spent waiting in hand() and
  /// drain(), seconds, so far.
  double sink_seconds() const;
  double wait_seconds() const { return wait_seconds_; }

 private:
  void run();
  void wait_locked(std::unique_lock<std::mutex>& lock, std::size_t frames);

  ScanSink& sink_;
  const std::size_t capacity_;
  const std::function<void(ScannedFrame&)> finish_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<ScannedFrame> queue_;  // frames waiting for the sink, in order
  std::size_t in_sink_ = 0;         // frames taken off the queue and not yet done
  std::size_t next_ticket_ = 0;     // the order of the next frame taken off the queue
  std::size_t turn_ = 0;            // the ticket of the next frame for ScanSink::frame
  bool stopping_ = false;
  std::exception_ptr error_;
  double sink_seconds_ = 0;                   // under mutex_: while in_sink_ was above 0, before busy_since_
  std::chrono::steady_clock::time_point busy_since_;  // under mutex_: when in_sink_ last left 0
  double wait_seconds_ = 0;  // the scan's thread only
  // The sink's parallel work runs in an arena of its own: a thread of the
  // scan waiting for its own tasks never picks up the sink's, and the sink's
  // thread never picks up the back end's (whose tasks can be long), so that
  // neither waits for the other's work.
  tbb::task_arena arena_;
  std::vector<std::thread> threads_;  // last: started once everything above is set up
};

}  // namespace snag
