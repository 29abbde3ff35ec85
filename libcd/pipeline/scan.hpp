// The scan: streams a cache's frames through a back end and hands each
// frame's events to a sink. The collisions of the step f -> f + 1, then
// frame f's intersections (asked of the back end in that order, the order of
// the frame's events) are found while frames f, f + 1 and f + 2 are held;
// frame f + 3 is read meanwhile on another thread, frame f + 2 is handed to
// the back end's prepare() before the work on frame f starts (frame f + 1
// was, before the work on f - 1), so that a back end may start the next step
// early, and the sink takes the frames before it on a thread of its own (one
// for the whole scan, fed through a bounded queue of two frames), so reading,
// uploading, detection and reporting overlap while the scan holds at most six
// frames and three event lists.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "libcd/pipeline/backend.hpp"
#include "libcd/pipeline/event.hpp"
#include "libcd/scene/frame_source.hpp"

namespace snag {

struct ScanSettings {
  bool collisions = true;     ///< CCD between consecutive frames
  bool intersections = true;  ///< static detection in each frame
  BackendSettings backend;
};

/// Per-frame (intersections) and per-step (collisions) event counts.
struct FrameSummary {
  std::size_t frame = 0;  ///< the cache's own 0-based frame index (FrameSource::frame_index)
  std::size_t collisions = 0, vertex_face = 0, edge_edge = 0, uncertain = 0;
  std::size_t intersections = 0;
};

/// One frame's results, as the scan hands them to a ScanSink.
struct ScannedFrame {
  std::size_t position = 0;       ///< 0-based position in the source
  double time = 0;                ///< FrameSource::frame_time
  FrameSummary summary;
  /// The frame's intersections and the collisions of the step that starts at
  /// it (frame set), in event_order. The sink may reorder or remove them.
  std::vector<Event>* events = nullptr;
  const std::vector<Vec3>* x = nullptr;       ///< the frame's positions
  const std::vector<Vec3>* x_next = nullptr;  ///< the next frame's, when there is a step; else null
};

/// Receives each frame as soon as it is done, in frame order, one call at a
/// time, on a thread of its own: the sink of frame f runs while frames f + 1
/// and f + 2 are scanned. The frame's buffers stay valid until the call returns.
/// Nothing is kept between calls: what the sink keeps is what the scan holds.
///
/// A sink may split its work: prepare() does what a frame needs of nothing
/// but itself, and may run on frames_at_once() frames at a time, each on a
/// thread of its own; frame() then takes each prepared frame, in frame
/// order, one call at a time, on the thread that prepared it. The frame's
/// buffers stay valid from prepare() until frame() returns.
class ScanSink {
 public:
  virtual ~ScanSink() = default;
  virtual void frame(ScannedFrame& frame) = 0;
  /// Frames that may be in prepare() at once (1: prepare() and frame() of a
  /// frame run before the next frame's prepare()).
  virtual std::size_t frames_at_once() const { return 1; }
  /// The frame's own work, before frame() is called on it.
  virtual void prepare(ScannedFrame& /*frame*/) {}
};

/// Frames that may wait for the sink or be in it while scan_cache goes on:
/// three, so that a sink can prepare two frames at once while a third waits,
/// and one slow frame (the first, which lists the most events) is taken up
/// by the next ones instead of stopping the scan. With two, a quick back end
/// waited for the first frame's listing: cloth_ball through snag-scan on the
/// CUDA back end, both detections, 12 frames, ran at 7.52 ms a step with two
/// and 4.56 with three (H100, the same call, median of 4); each more costs a
/// frame's events and positions of host memory.
constexpr std::size_t kScanFramesInSink = 3;

/// What the scan adds up: counts and times, never events.
struct ScanTotals {
  std::size_t frames = 0;
  PipelineStats stats;        ///< summed over all frames and steps
  double read_seconds = 0;    ///< time spent reading frames (overlapping detection)
  double sink_seconds = 0;       ///< time spent in the sink (writing the report), on its thread
  double sink_wait_seconds = 0;  ///< of it, the time the scan waited for the sink
  double total_seconds = 0;
};

/// Called after each frame is done with (frame index, frame count).
using ProgressCallback = std::function<void(std::size_t, std::size_t)>;

/// Scans every frame of `source` with `backend`, handing each frame to
/// `sink`. Memory does not grow with the number of frames. Throws what the
/// source or the sink throws.
ScanTotals scan_cache(const FrameSource& source, Backend& backend, const ScanSettings& settings, ScanSink& sink,
                      const ProgressCallback& progress = {});

/// Every event and frame summary of a scan, kept in memory: for tests and
/// benchmarks on small caches.
struct ScanResult {
  std::vector<Event> events;  ///< in event_order
  std::vector<FrameSummary> frames;
  PipelineStats stats;
  double read_seconds = 0;
  double total_seconds = 0;
};

ScanResult scan_cache(const FrameSource& source, Backend& backend, const ScanSettings& settings,
                      const ProgressCallback& progress = {});

}  // namespace snag
