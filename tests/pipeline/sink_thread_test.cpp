// The scan's sink thread: frames reach the sink in order, one at a time; the
// scan waits once `capacity` frames are queued or in the sink, so that it is
// never more than that many frames ahead of the report; what the sink throws
// comes out of the scan's side, and no frame after it reaches the sink. A
// sink that prepares two frames at once gets them on two threads, and each
// frame's frame() in order, on the thread that prepared it.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "libcd/pipeline/scan.hpp"
#include "libcd/pipeline/sink_thread.hpp"

namespace snag {
namespace {

/// Records the positions it gets; holds each frame until released (or not
/// at all if `gated` is false); throws at `failing`.
class GatedSink final : public ScanSink {
 public:
  GatedSink(bool gated, std::size_t failing) : gated_(gated), failing_(failing) {}
  void frame(ScannedFrame& frame) override {
    std::unique_lock<std::mutex> lock(mutex_);
    seen.push_back(frame.position);
    changed_.notify_all();
    changed_.wait(lock, [&] { return !gated_ || released_ > frame.position; });
    if (frame.position == failing_) throw std::runtime_error("sink failed");
  }
  void release_up_to(std::size_t position) {
    std::lock_guard<std::mutex> lock(mutex_);
    released_ = position + 1;
    changed_.notify_all();
  }
  void wait_until_seen(std::size_t count) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return seen.size() >= count; });
  }
  std::vector<std::size_t> seen;  // under mutex_ until the thread is done

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  bool gated_;
  std::size_t failing_;
  std::size_t released_ = 0;
};

ScannedFrame at(std::size_t position) {
  ScannedFrame frame;
  frame.position = position;
  return frame;
}

TEST(SinkThread, HandsFramesInOrderAndWaitsWhenFull) {
  GatedSink sink(true, 99);
  SinkThread thread(sink, 2);
  thread.hand(at(0));
  thread.hand(at(1));  // frame 0 in the sink, frame 1 queued: full
  sink.wait_until_seen(1);
  std::atomic<bool> handed{false};
  std::thread third([&] {
    thread.hand(at(2));
    handed = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(handed) << "a third frame went in while two were held";
  sink.release_up_to(0);
  third.join();
  EXPECT_TRUE(handed);
  sink.release_up_to(2);
  thread.drain();
  EXPECT_EQ(sink.seen, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_GE(thread.wait_seconds(), 0.0);
  EXPECT_GT(thread.sink_seconds(), 0.0);
}

// Records, for each frame, whether `finish` had run on it and on which thread.
class FinishedSink final : public ScanSink {
 public:
  void frame(ScannedFrame& frame) override {
    finished.push_back(frame.summary.collisions == 1000 + frame.position);
    threads.push_back(std::this_thread::get_id());
  }
  std::vector<bool> finished;
  std::vector<std::thread::id> threads;
};

TEST(SinkThread, FinishesEachFrameOnItsOwnThreadJustBeforeTheSink) {
  FinishedSink sink;
  std::vector<std::size_t> finished_order;
  std::vector<std::thread::id> finish_threads;
  {
    SinkThread thread(sink, 2, [&](ScannedFrame& frame) {
      frame.summary.collisions = 1000 + frame.position;  // what the sink must see
      finished_order.push_back(frame.position);
      finish_threads.push_back(std::this_thread::get_id());
    });
    for (std::size_t p = 0; p < 6; ++p) thread.hand(at(p));
    thread.drain();
  }
  EXPECT_EQ(finished_order, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(sink.finished, std::vector<bool>(6, true));
  ASSERT_EQ(finish_threads.size(), sink.threads.size());
  for (std::size_t p = 0; p < finish_threads.size(); ++p) {
    EXPECT_NE(finish_threads[p], std::this_thread::get_id()) << "frame " << p << " was finished on the scan's thread";
    EXPECT_EQ(finish_threads[p], sink.threads[p]) << "frame " << p;
  }
}

/// Hands frames 0 .. 49 to a sink thread of room 2 and waits for them; the
/// message of the runtime_error that came out ("" when none did), once the
/// thread has ended.
std::string error_of_handing(ScanSink& sink) {
  SinkThread thread(sink, 2);
  try {
    for (std::size_t f = 0; f < 50; ++f) thread.hand(at(f));
    thread.drain();
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST(SinkThread, ASinkErrorComesOutAndNoLaterFrameReachesTheSink) {
  GatedSink sink(false, 1);
  EXPECT_EQ(error_of_handing(sink), "sink failed");
  EXPECT_EQ(sink.seen, (std::vector<std::size_t>{0, 1}));
}

/// Prepares two frames at once: the prepare() of an even frame waits (up to
/// a time that fails the test rather than hangs it) until the odd frame
/// after it is being prepared too. Records the order of frame() and the
/// threads of both calls; throws in prepare() at `failing`.
class TwoAtOnceSink final : public ScanSink {
 public:
  explicit TwoAtOnceSink(std::size_t failing) : failing_(failing) {}
  std::size_t frames_at_once() const override { return 2; }
  void prepare(ScannedFrame& frame) override {
    std::unique_lock<std::mutex> lock(mutex_);
    preparing.push_back(frame.position);
    prepare_threads[frame.position] = std::this_thread::get_id();
    changed_.notify_all();
    if (frame.position % 2 == 0) {
      const bool met = changed_.wait_for(lock, std::chrono::seconds(20), [&] {
        return std::find(preparing.begin(), preparing.end(), frame.position + 1) != preparing.end();
      });
      if (!met) waited_alone.push_back(frame.position);
    }
    if (frame.position == failing_) throw std::runtime_error("prepare failed");
  }
  void frame(ScannedFrame& frame) override {
    std::lock_guard<std::mutex> lock(mutex_);
    framed.push_back(frame.position);
    frame_threads[frame.position] = std::this_thread::get_id();
  }
  // Under mutex_ until the threads are done.
  std::vector<std::size_t> preparing, framed, waited_alone;
  std::map<std::size_t, std::thread::id> prepare_threads, frame_threads;

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::size_t failing_;
};

TEST(SinkThread, PreparesTwoFramesAtOnceAndHandsThemToTheSinkInOrder) {
  TwoAtOnceSink sink(99);
  {
    SinkThread thread(sink, 2);
    for (std::size_t p = 0; p < 8; ++p) thread.hand(at(p));
    thread.drain();
    EXPECT_GT(thread.sink_seconds(), 0.0);
  }
  EXPECT_TRUE(sink.waited_alone.empty()) << "frame " << sink.waited_alone.front() << " was prepared alone";
  EXPECT_EQ(sink.framed, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 6, 7}));
  std::set<std::thread::id> threads;
  for (std::size_t p = 0; p < 8; ++p) {
    EXPECT_EQ(sink.frame_threads[p], sink.prepare_threads[p]) << "frame " << p << " left the thread that prepared it";
    EXPECT_NE(sink.prepare_threads[p], std::this_thread::get_id()) << "frame " << p;
    threads.insert(sink.prepare_threads[p]);
  }
  EXPECT_EQ(threads.size(), 2u);
}

TEST(SinkThread, AFailedPrepareComesOutAfterTheFramesBeforeItAndNoLaterFrameReachesTheSink) {
  TwoAtOnceSink sink(2);
  EXPECT_EQ(error_of_handing(sink), "prepare failed");
  EXPECT_EQ(sink.framed, (std::vector<std::size_t>{0, 1}));
}

/// Frames of one triangle; reads cost nothing.
class TriangleSource final : public FrameSource {
 public:
  explicit TriangleSource(std::size_t frames) : scene_({make_object("tri", 3, {Triangle{0, 1, 2}})}), frames_(frames) {}
  const Scene& scene() const override { return scene_; }
  std::size_t frame_count() const override { return frames_; }
  void read_frame(std::size_t i, std::vector<Vec3>& x) const override {
    x = {Vec3{double(i), 0, 0}, Vec3{double(i), 1, 0}, Vec3{double(i), 0, 1}};
  }
  std::string description() const override { return "one triangle"; }

 private:
  Scene scene_;
  std::size_t frames_;
};

/// A slow sink that checks how far ahead the scan is when it gets each frame.
class AheadSink final : public ScanSink {
 public:
  explicit AheadSink(const std::atomic<std::size_t>& scanned) : scanned_(scanned) {}
  void frame(ScannedFrame& frame) override {
    std::this_thread::sleep_for(std::chrono::milliseconds(3));
    const std::size_t ahead = scanned_.load() - frame.position;  // frames handed from p on
    most_ahead = std::max(most_ahead, ahead);
    EXPECT_EQ((*frame.x)[0].x, double(frame.position)) << "the frame's positions were overwritten";
  }
  std::size_t most_ahead = 0;

 private:
  const std::atomic<std::size_t>& scanned_;
};

TEST(SinkThread, TheScanIsNeverMoreFramesAheadOfTheSinkThanItsRoom) {
  const TriangleSource source(40);
  auto backend = make_cpu_backend();
  backend->bind(source.scene(), BackendSettings{});
  std::atomic<std::size_t> scanned{0};
  AheadSink sink(scanned);
  const ScanTotals totals =
      scan_cache(source, *backend, ScanSettings{}, sink, [&](std::size_t done, std::size_t) { scanned = done; });
  EXPECT_EQ(totals.frames, 40u);
  // While frame p is in the sink, the frames after it up to the room
  // (kScanFramesInSink frames queued or in the sink) may be handed over, and
  // the scan work on the next: frames handed over (counted by the progress
  // callback) are never past p + kScanFramesInSink - 1.
  EXPECT_LE(sink.most_ahead, kScanFramesInSink);
  EXPECT_EQ(sink.most_ahead, kScanFramesInSink) << "a slow sink should have let the queue fill";
  EXPECT_GT(totals.sink_wait_seconds, 0.0);
}

}  // namespace
}  // namespace snag
