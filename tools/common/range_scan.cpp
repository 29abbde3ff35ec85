#include "tools/common/range_scan.hpp"

#include <algorithm>
#include <cmath>

namespace snag::tools {

namespace {

// The frames first..last of a source, as positions 0..last - first.
class FrameWindow : public FrameSource {
 public:
  FrameWindow(const FrameSource& source, const StepRange& range) : source_(source), range_(range) {}
  const Scene& scene() const override { return source_.scene(); }
  std::size_t frame_count() const override { return range_.last - range_.first + 1; }
  double frame_time(std::size_t i) const override { return source_.frame_time(range_.first + i); }
  std::size_t frame_index(std::size_t i) const override { return source_.frame_index(range_.first + i); }
  void read_frame(std::size_t i, std::vector<Vec3>& positions) const override {
    source_.read_frame(range_.first + i, positions);
  }
  std::string description() const override { return source_.description(); }

 private:
  const FrameSource& source_;
  StepRange range_;
};

// Skips the intersections of the overlap frame (the next range finds them),
// so that neither its events nor its counters are counted twice. The scan
// asks for one frame's intersections after another's, in order.
class OverlapBackend : public Backend {
 public:
  OverlapBackend(Backend& backend, std::size_t skipped_call) : backend_(backend), skipped_call_(skipped_call) {}
  std::string name() const override { return backend_.name(); }
  void bind(const Scene& scene, const BackendSettings& settings) override { backend_.bind(scene, settings); }
  void collisions(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<Event>& events) override {
    last_skipped_ = false;
    backend_.collisions(x_t0, x_t1, events);
  }
  void intersections(const std::vector<Vec3>& x, std::vector<Event>& events) override {
    last_skipped_ = calls_++ == skipped_call_;
    if (!last_skipped_) backend_.intersections(x, events);
  }
  void prepare(const std::vector<Vec3>& x) override { backend_.prepare(x); }
  const PipelineStats& stats() const override { return last_skipped_ ? nothing_ : backend_.stats(); }

 private:
  Backend& backend_;
  std::size_t skipped_call_;
  std::size_t calls_ = 0;
  bool last_skipped_ = false;
  PipelineStats nothing_;
};

// Gives the sink positions in the whole source and keeps the overlap frame from it.
class WindowSink : public ScanSink {
 public:
  WindowSink(ScanSink& sink, const StepRange& range) : sink_(sink), range_(range) {}
  void frame(ScannedFrame& frame) override {
    frame.position += range_.first;
    if (range_.overlap && frame.position == range_.last) return;
    sink_.frame(frame);
  }

 private:
  ScanSink& sink_;
  StepRange range_;
};

}  // namespace

std::vector<StepRange> split_steps(std::size_t frame_count, std::size_t parts, double merge_cost) {
  std::vector<StepRange> ranges(parts);
  if (frame_count == 0 || parts == 0) return ranges;
  const std::size_t steps = frame_count - 1;
  if (steps == 0) {
    ranges[0] = {0, 0, false, false};
    return ranges;
  }
  const std::size_t used = std::min(parts, steps);
  const double ratio = 1.0 - std::clamp(merge_cost, 0.0, 0.9);
  std::vector<double> before(used + 1, 0.0);  // the weights of the ranges before each
  for (std::size_t r = 0; r < used; ++r) before[r + 1] = before[r] + std::pow(ratio, static_cast<double>(used - 1 - r));
  std::size_t first = 0;
  for (std::size_t r = 0; r < used; ++r) {
    const auto ideal = static_cast<std::size_t>(static_cast<double>(steps) * before[r + 1] / before[used]);
    // At least one step here and one for each range after.
    const std::size_t last = r + 1 == used ? steps : std::clamp(ideal, first + 1, steps - (used - 1 - r));
    ranges[r] = {first, last, r + 1 < used, false};
    first = last;
  }
  return ranges;
}

ScanTotals scan_range(const FrameSource& source, const StepRange& range, Backend& backend,
                      const ScanSettings& settings, ScanSink& sink, const ProgressCallback& progress) {
  if (range.empty) return {};
  const FrameWindow window(source, range);
  const std::size_t skipped_call = range.overlap ? range.last - range.first : static_cast<std::size_t>(-1);
  OverlapBackend overlap_backend(backend, skipped_call);
  WindowSink window_sink(sink, range);
  ProgressCallback window_progress;
  if (progress) {
    window_progress = [&](std::size_t done, std::size_t) {
      progress(std::min(range.first + done, range.last + !range.overlap), source.frame_count());
    };
  }
  ScanTotals totals = scan_cache(window, overlap_backend, settings, window_sink, window_progress);
  totals.frames -= range.overlap;
  return totals;
}

}  // namespace snag::tools
