// scan_cache reads frame f + 3 on another thread and hands frame f + 2 to the
// back end's prepare() before frame f is worked on: the back end must still see
// every frame, in order, unchanged from prepare() to its use, and a read error
// must come out of the scan as the source threw it; the sink of frame f runs
// while frame f + 1 is scanned, and must see its frames intact.
#include "libcd/pipeline/scan.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "libcd/core/error.hpp"

namespace snag {
namespace {

/// Frames of one triangle whose first vertex's x is the frame number; frame
/// `failing` throws InputError instead.
class CountingSource final : public FrameSource {
 public:
  CountingSource(std::size_t frames, std::size_t failing)
      : scene_({make_object("tri", 3, {Triangle{0, 1, 2}})}), frames_(frames), failing_(failing) {}
  const Scene& scene() const override { return scene_; }
  std::size_t frame_count() const override { return frames_; }
  std::size_t frame_index(std::size_t i) const override { return 10 + i; }
  void read_frame(std::size_t i, std::vector<Vec3>& positions) const override {
    if (i == failing_) throw InputError({"frames.pc2", 0, i}, "truncated");
    positions = {Vec3{double(i), 0, 0}, Vec3{double(i), 1, 0}, Vec3{double(i), 0, 1}};
  }
  std::string description() const override { return "counting frames"; }

 private:
  Scene scene_;
  std::size_t frames_, failing_;
};

/// Records the frame numbers of every call, and checks that each
/// collisions() call gets as x_t1 a vector prepared before, unchanged.
class RecordingBackend final : public Backend {
 public:
  std::string name() const override { return "recording"; }
  void bind(const Scene&, const BackendSettings&) override {}
  void collisions(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<Event>&) override {
    calls.push_back("c" + std::to_string(int(x_t0[0].x)) + "-" + std::to_string(int(x_t1[0].x)));
    bool was_prepared = false;
    for (const auto& [address, copy] : prepared) {
      if (address != &x_t1 || copy[0].x != x_t1[0].x) continue;
      was_prepared = true;
      EXPECT_TRUE(copy == x_t1) << "the prepared frame changed before its use";
    }
    EXPECT_TRUE(was_prepared) << "x_t1 is a prepared vector";
  }
  void intersections(const std::vector<Vec3>& x, std::vector<Event>& events) override {
    calls.push_back("i" + std::to_string(int(x[0].x)));
    Event e;
    e.kind = EventKind::kIntersection;
    events.push_back(e);
  }
  void prepare(const std::vector<Vec3>& x) override {
    calls.push_back("p" + std::to_string(int(x[0].x)));
    prepared.emplace_back(&x, x);
  }
  const PipelineStats& stats() const override { return stats_; }

  std::vector<std::string> calls;
  std::vector<std::pair<const std::vector<Vec3>*, std::vector<Vec3>>> prepared;

 private:
  PipelineStats stats_;
};

TEST(ScanCache, SeesEveryFrameInOrderWithTheFramesAheadPreparedFirst) {
  const CountingSource source(5, 99);
  RecordingBackend backend;
  const ScanResult result = scan_cache(source, backend, ScanSettings{});
  // Each step's collisions, then its first frame's intersections: the order
  // of a frame's events; the frame after the step is prepared first.
  const std::vector<std::string> expected = {"p1", "p2",   "c0-1", "i0",   "p3", "c1-2", "i1",
                                             "p4", "c2-3", "i2",   "c3-4", "i3", "i4"};
  EXPECT_EQ(backend.calls, expected);
  ASSERT_EQ(result.frames.size(), 5u);
  for (std::size_t f = 0; f < 5; ++f) {
    EXPECT_EQ(result.frames[f].frame, 10 + f);
    EXPECT_EQ(result.frames[f].intersections, 1u);
  }
  EXPECT_EQ(result.events.size(), 5u);
}

TEST(ScanCache, IntersectionsOnlyPrepareNothing) {
  const CountingSource source(3, 99);
  RecordingBackend backend;
  ScanSettings settings;
  settings.collisions = false;
  (void)scan_cache(source, backend, settings);
  const std::vector<std::string> expected = {"i0", "i1", "i2"};
  EXPECT_EQ(backend.calls, expected);
}

/// A slow source that counts the reads of frames after the first under way,
/// and the most at once.
class SlowSource final : public FrameSource {
 public:
  explicit SlowSource(std::size_t frames) : scene_({make_object("tri", 3, {Triangle{0, 1, 2}})}), frames_(frames) {}
  const Scene& scene() const override { return scene_; }
  std::size_t frame_count() const override { return frames_; }
  void read_frame(std::size_t i, std::vector<Vec3>& positions) const override {
    const int now = i > 0 ? ++reading_ : 0;
    int seen = most_.load();
    while (now > seen && !most_.compare_exchange_weak(seen, now)) {
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    positions = {Vec3{double(i), 0, 0}, Vec3{double(i), 1, 0}, Vec3{double(i), 0, 1}};
    if (i > 0) --reading_;
  }
  std::string description() const override { return "slow frames"; }
  int most() const { return most_; }

 private:
  Scene scene_;
  std::size_t frames_;
  mutable std::atomic<int> reading_{0}, most_{0};
};

// Reads slower than the steps: once a step has waited for its frame, the
// frames after it are read two at a time, each into a buffer of its own,
// and the steps still see their frames, in order.
TEST(ScanCache, ReadsTwoFramesAtATimeOnceAStepWaitsForItsFrame) {
  const SlowSource source(8);
  RecordingBackend backend;
  const ScanResult result = scan_cache(source, backend, ScanSettings{});
  EXPECT_EQ(source.most(), 2);
  ASSERT_EQ(result.frames.size(), 8u);
  std::vector<std::string> collisions;
  for (const std::string& call : backend.calls)
    if (call[0] == 'c') collisions.push_back(call);
  EXPECT_EQ(collisions, (std::vector<std::string>{"c0-1", "c1-2", "c2-3", "c3-4", "c4-5", "c5-6", "c6-7"}));
}

TEST(ScanCache, AReadErrorAheadComesOutOfTheScan) {
  for (std::size_t failing : {std::size_t(1), std::size_t(3), std::size_t(5)}) {
    SCOPED_TRACE(failing);
    const CountingSource source(6, failing);
    RecordingBackend backend;
    try {
      (void)scan_cache(source, backend, ScanSettings{});
      ADD_FAILURE() << "no error";
    } catch (const InputError& error) {
      EXPECT_EQ(error.where().frame, failing);
      EXPECT_EQ(error.message(), "truncated");
    }
    // Nothing past the frame before the bad one was worked on.
    for (const std::string& call : backend.calls) EXPECT_LT(call.back() - '0', int(failing)) << call;
  }
}

/// A slow sink: checks that each frame it gets holds that frame's positions
/// (and the next frame's, for a step) while the scan goes on with the next
/// frame, in order; throws at frame `failing`.
class CheckingSink final : public ScanSink {
 public:
  explicit CheckingSink(std::size_t failing) : failing_(failing) {}
  void frame(ScannedFrame& frame) override {
    positions.push_back(frame.position);
    const double f = static_cast<double>(frame.position);
    for (int pass = 0; pass < 3; ++pass) {  // the scan reads ahead meanwhile: the buffers must hold
      EXPECT_EQ((*frame.x)[0].x, f);
      if (frame.x_next) EXPECT_EQ((*frame.x_next)[0].x, f + 1);
      ASSERT_EQ(frame.events->size(), 1u);
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (frame.position == failing_) throw std::runtime_error("sink failed");
  }
  std::vector<std::size_t> positions;

 private:
  std::size_t failing_;
};

TEST(ScanCache, TheSinkGetsEachFrameInOrderWithItsPositionsIntact) {
  const CountingSource source(9, 99);
  RecordingBackend backend;
  CheckingSink sink(99);
  const ScanTotals totals = scan_cache(source, backend, ScanSettings{}, sink);
  EXPECT_EQ(totals.frames, 9u);
  EXPECT_EQ(sink.positions, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
  EXPECT_GT(totals.sink_seconds, 0.0);
}

TEST(ScanCache, ASinkErrorComesOutOfTheScan) {
  const CountingSource source(9, 99);
  RecordingBackend backend;
  CheckingSink sink(4);
  EXPECT_THROW((void)scan_cache(source, backend, ScanSettings{}, sink), std::runtime_error);
  EXPECT_EQ(sink.positions.back(), 4u);
}

}  // namespace
}  // namespace snag
