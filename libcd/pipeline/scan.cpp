#include "libcd/pipeline/scan.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <deque>
#include <future>
#include <tuple>

#include "libcd/pipeline/sink_thread.hpp"

namespace snag {

namespace {

using Clock = std::chrono::steady_clock;

// Events per task of the passes over a frame's events.
constexpr std::size_t kEventsPerTask = 8192;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

void add_levels(std::vector<std::size_t>& total, const std::vector<std::size_t>& step) {
  if (total.size() < step.size()) total.resize(step.size(), 0);
  for (std::size_t i = 0; i < step.size(); ++i) total[i] += step[i];
}

// Sums the counters; the cell size and grid are the last step's.
void add_broad(BroadPhaseStats& total, const BroadPhaseStats& s) {
  total.cell_size = s.cell_size;
  std::copy(std::begin(s.grid_dims), std::end(s.grid_dims), std::begin(total.grid_dims));
  std::size_t BroadPhaseStats::*counters[] = {
      &BroadPhaseStats::cells_used, &BroadPhaseStats::cells_subdivided, &BroadPhaseStats::root_triangles, &BroadPhaseStats::triangles_subdivided,
      &BroadPhaseStats::time_halvings, &BroadPhaseStats::oversized_leaves, &BroadPhaseStats::leaf_triangles,
      &BroadPhaseStats::registrations, &BroadPhaseStats::home_registrations,
      &BroadPhaseStats::phantom_registrations, &BroadPhaseStats::duplicate_registrations_removed,
      &BroadPhaseStats::tests, &BroadPhaseStats::culled_by_boxes, &BroadPhaseStats::same_root_tests,
      &BroadPhaseStats::removed_by_time_slots,
      &BroadPhaseStats::removed_by_control_bits, &BroadPhaseStats::removed_by_extended_control_bits,
      &BroadPhaseStats::fallback_tests, &BroadPhaseStats::tests_after_control_bits,
      &BroadPhaseStats::duplicate_root_pair_tests, &BroadPhaseStats::duplicate_culled_tests,
      &BroadPhaseStats::culled_by_dop, &BroadPhaseStats::triangle_pairs, &BroadPhaseStats::left_out_apart,
      &BroadPhaseStats::separated_triangle_pairs,
      &BroadPhaseStats::vf_before_culling, &BroadPhaseStats::vf_after_culling, &BroadPhaseStats::ee_before_culling,
      &BroadPhaseStats::ee_after_culling, &BroadPhaseStats::candidates};
  for (auto field : counters) total.*field += s.*field;
  total.memory_bytes = std::max(total.memory_bytes, s.memory_bytes);
  total.deepest_level = std::max(total.deepest_level, s.deepest_level);
  add_levels(total.triangles_per_level, s.triangles_per_level);
  add_levels(total.subdivided_per_level, s.subdivided_per_level);
  add_levels(total.halved_per_level, s.halved_per_level);
  double BroadPhaseStats::*seconds[] = {&BroadPhaseStats::seconds_bounds, &BroadPhaseStats::seconds_subdivision,
                                        &BroadPhaseStats::seconds_registration, &BroadPhaseStats::seconds_pairs,
                                        &BroadPhaseStats::seconds_features, &BroadPhaseStats::seconds_total};
  for (auto field : seconds) total.*field += s.*field;
}

void add_narrow(NarrowPhaseStats& total, const NarrowPhaseStats& s) {
  std::size_t NarrowPhaseStats::*counters[] = {
      &NarrowPhaseStats::vf_tests,   &NarrowPhaseStats::vf_yes,         &NarrowPhaseStats::vf_no,
      &NarrowPhaseStats::vf_uncertain, &NarrowPhaseStats::ee_tests,     &NarrowPhaseStats::ee_yes,
      &NarrowPhaseStats::ee_no,      &NarrowPhaseStats::ee_uncertain,   &NarrowPhaseStats::certified,
      &NarrowPhaseStats::certified_true, &NarrowPhaseStats::triangle_tests,
      &NarrowPhaseStats::triangles_intersecting};
  for (auto field : counters) total.*field += s.*field;
  total.predicate_calls += s.predicate_calls;
  total.predicate_exact += s.predicate_exact;
  total.seconds_ccd += s.seconds_ccd;
  total.seconds_certify += s.seconds_certify;
  total.seconds_static += s.seconds_static;
  total.seconds_ccd_events += s.seconds_ccd_events;
  total.seconds_static_events += s.seconds_static_events;
  total.seconds_ccd_device += s.seconds_ccd_device;
  total.seconds_static_device += s.seconds_static_device;
}

}  // namespace

void PipelineStats::add(const PipelineStats& other) {
  steps += other.steps;
  frames += other.frames;
  if (other.steps > 0) add_broad(ccd_broad, other.ccd_broad);
  if (other.frames > 0) add_broad(static_broad, other.static_broad);
  add_narrow(narrow, other.narrow);
}

namespace {

constexpr std::size_t kFramesInSink = kScanFramesInSink;
// Frames read at once, ahead of the step, at most: one, and two once a step
// has waited for its frame. A text format (OBJ, ASCII PLY) can take as long
// to read as a step of the GPU back end, and two reads at a time keep it off
// the step's path; a quick read (binary PLY) stays alone, off the workers
// of the step and the sink.
constexpr std::size_t kFramesReading = 2;
// Frame buffers: the frames in the sink (and the step's next frame of the
// last of them), the step the back end works on and the frame after it
// (prepared, so that a back end can start the next step), and the ones being
// read.
constexpr std::size_t kFrameBuffers = kFramesInSink + 3 + kFramesReading;
// Event lists: one per frame in the sink, and the one being filled.
constexpr std::size_t kEventBuffers = kFramesInSink + 1;

// Sets each event's frame, counts the collisions' types (the first
// `collisions` events), and puts the list in event_order if it is not: each
// back end returns its list in order and collisions come before
// intersections, so one pass over the events (on all threads) checks the
// order and no sort is needed.
void finish_events(std::vector<Event>& events, std::size_t collisions, FrameSummary& summary) {
  struct Pass {
    std::size_t vertex_face = 0, edge_edge = 0, uncertain = 0;
    bool ordered = true;
  };
  // Every event gets the same frame: the order is that of the rest of the key.
  auto before = [](const Event& x, const Event& y) {
    return std::make_tuple(x.kind, x.type, x.a, x.b) < std::make_tuple(y.kind, y.type, y.a, y.b);
  };
  const std::size_t frame = summary.frame;
  const Pass pass = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, events.size(), kEventsPerTask), Pass{},
      [&](const tbb::blocked_range<std::size_t>& range, Pass sum) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) {
          Event& event = events[i];
          event.frame = frame;
          if (i < collisions) {
            sum.vertex_face += event.type == ContactType::kVertexFace;
            sum.edge_edge += event.type == ContactType::kEdgeEdge;
            sum.uncertain += event.certainty == Certainty::kUncertain;
          }
          if (sum.ordered && i > 0 && before(event, events[i - 1])) sum.ordered = false;
        }
        return sum;
      },
      [](Pass left, const Pass& right) {
        left.vertex_face += right.vertex_face;
        left.edge_edge += right.edge_edge;
        left.uncertain += right.uncertain;
        left.ordered = left.ordered && right.ordered;
        return left;
      });
  summary.vertex_face += pass.vertex_face;
  summary.edge_edge += pass.edge_edge;
  summary.uncertain += pass.uncertain;
  if (!pass.ordered) std::sort(events.begin(), events.end(), event_order);
}

}  // namespace

ScanTotals scan_cache(const FrameSource& source, Backend& backend, const ScanSettings& settings, ScanSink& sink,
                      const ProgressCallback& progress) {
  const auto start = Clock::now();
  ScanTotals totals;
  const std::size_t frame_count = source.frame_count();
  const bool detect = settings.collisions || settings.intersections;
  // Frame i lives in frames[i % kFrameBuffers] and its events in
  // events[i % kEventBuffers], filled by the back end and then handed to
  // the sink's thread.
  std::vector<Vec3> frames[kFrameBuffers];
  std::vector<Event> events[kEventBuffers];
  // Frames being read, in frame order: at most `frames_reading`, frame
  // `next_read` the next to start. After the buffers: joined before they go.
  std::deque<std::future<double>> reading;
  std::size_t next_read = 1, frames_reading = 1;
  auto read_ahead = [&](std::size_t last) {
    for (; next_read <= last && next_read < frame_count; ++next_read) {
      reading.push_back(std::async(std::launch::async, [&source, &frames, i = next_read] {
        const auto read_start = Clock::now();
        source.read_frame(i, frames[i % kFrameBuffers]);
        return seconds_since(read_start);
      }));
    }
  };
  try {
    // After the buffers: on the way out it waits for the frames in the sink
    // and drops the others, so that nothing uses the buffers when they go.
    // Each frame's events are finished (their frame set, counted, put in
    // order) on the sink's thread, so that the scan goes on to the next step
    // at once.
    SinkThread sinking(sink, kFramesInSink, [](ScannedFrame& frame) {
      finish_events(*frame.events, frame.summary.collisions, frame.summary);
    });
    // Frame i is read ahead, then prepared (for collisions) and the frames
    // after it read, while frame i - 2 is worked on. Frame i > 1 was begun a
    // step ago: when it is not read yet, reading is slower than the steps,
    // and two frames are read at a time from then on.
    auto take_read = [&](std::size_t i) {
      std::future<double> read = std::move(reading.front());
      reading.pop_front();
      if (i > 1 && read.wait_for(std::chrono::seconds(0)) != std::future_status::ready) frames_reading = kFramesReading;
      totals.read_seconds += read.get();
      if (settings.collisions) backend.prepare(frames[i % kFrameBuffers]);
      read_ahead(i + frames_reading);
    };
    if (frame_count > 0) {
      // Frame 1 is read on a reading thread while frame 0 is read here.
      const bool step = frame_count > 1 && detect;
      if (step) read_ahead(1);
      const auto read_start = Clock::now();
      source.read_frame(0, frames[0]);
      totals.read_seconds += seconds_since(read_start);
      if (step) take_read(1);
    }
    for (std::size_t f = 0; f < frame_count; ++f) {
      const std::vector<Vec3>& current = frames[f % kFrameBuffers];
      const std::vector<Vec3>& next = frames[(f + 1) % kFrameBuffers];
      const bool has_next = f + 1 < frame_count && detect;
      if (f + 2 < frame_count && detect) take_read(f + 2);
      ScannedFrame done;
      done.position = f;
      done.time = source.frame_time(f);
      done.summary.frame = source.frame_index(f);
      // The collisions, then the intersections, straight into the frame's
      // list (the order of events), each asked for in that order.
      std::vector<Event>& frame_events = events[f % kEventBuffers];
      frame_events.clear();
      if (settings.collisions && has_next) {
        backend.collisions(current, next, frame_events);
        totals.stats.add(backend.stats());
        done.summary.collisions = frame_events.size();
      }
      if (settings.intersections) {
        backend.intersections(current, frame_events);
        totals.stats.add(backend.stats());
        done.summary.intersections = frame_events.size() - done.summary.collisions;
      }
      done.events = &frame_events;
      done.x = &current;
      done.x_next = has_next ? &next : nullptr;
      sinking.hand(done);  // waits while kFramesInSink frames are queued or in the sink
      ++totals.frames;
      if (progress) progress(f + 1, frame_count);
    }
    sinking.drain();
    totals.sink_seconds = sinking.sink_seconds();
    totals.sink_wait_seconds = sinking.wait_seconds();
  } catch (...) {
    for (std::future<double>& read : reading) read.wait();  // the sink's thread has ended by now; each is valid
    throw;
  }
  totals.total_seconds = seconds_since(start);
  return totals;
}

namespace {

class CollectingSink : public ScanSink {
 public:
  explicit CollectingSink(ScanResult& result) : result_(result) {}
  void frame(ScannedFrame& frame) override {
    result_.frames.push_back(frame.summary);
    result_.events.insert(result_.events.end(), frame.events->begin(), frame.events->end());
  }

 private:
  ScanResult& result_;
};

}  // namespace

ScanResult scan_cache(const FrameSource& source, Backend& backend, const ScanSettings& settings,
                      const ProgressCallback& progress) {
  ScanResult result;
  CollectingSink sink(result);
  const ScanTotals totals = scan_cache(source, backend, settings, sink, progress);
  result.stats = totals.stats;
  result.read_seconds = totals.read_seconds;
  result.total_seconds = totals.total_seconds;
  return result;
}

}  // namespace snag
