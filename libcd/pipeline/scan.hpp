// The scan: streams a cache's frames through a back end and gathers events
// and stage counts. Frame f's intersections and the collisions of the step
// f -> f + 1 are found while frames f and f + 1 are held; frame f + 2 is read
// meanwhile on another thread, and frame f + 1 is handed to the back end's
// prepare() before the work on frame f starts, so reading and uploading
// overlap detection.
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

struct ScanResult {
  std::vector<Event> events;  ///< in event_order
  std::vector<FrameSummary> frames;
  PipelineStats stats;        ///< summed over all frames and steps
  double read_seconds = 0;    ///< time spent reading frames (overlapping detection)
  double total_seconds = 0;
};

/// Called after each frame is done with (frame index, frame count).
using ProgressCallback = std::function<void(std::size_t, std::size_t)>;

/// Scans every frame of `source` with `backend`. Throws what the source throws.
ScanResult scan_cache(const FrameSource& source, Backend& backend, const ScanSettings& settings,
                      const ProgressCallback& progress = {});

}  // namespace snag
