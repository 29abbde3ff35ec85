// A scan split into ranges of steps, one per process: range r scans the
// frames first..last of the selection and the steps between them; it
// overlaps the next range by its last frame, which it reads only for the
// step into it (that frame's intersections and the step out of it are the
// next range's). Handed to the sink in order, the ranges' frames are the
// frames one scan would hand, event for event.
#pragma once

#include <cstddef>
#include <vector>

#include "libcd/pipeline/scan.hpp"

namespace snag::tools {

/// Positions first..last (inclusive) of a source. `overlap`: `last` belongs
/// to the next range (read for the step into it only).
struct StepRange {
  std::size_t first = 0, last = 0;
  bool overlap = false;
  bool empty = true;  ///< nothing to scan: more ranges than steps
};

/// Splits `frame_count` frames into `parts` ranges, in order, for one
/// process that takes the ranges' frames in order after scanning the first
/// range itself, at `merge_cost` (in [0, 0.9]) of a scan's time per frame.
/// Range r gets steps in proportion to (1 - merge_cost)^(parts - 1 - r), so
/// that the taker, following each range as it is scanned, ends each one
/// when its scanner does (range r takes (1 - merge_cost) of range r + 1's
/// time to scan, and merge_cost of it to take); 0: nearly equal step
/// counts. Every range that is used gets at least one step; ranges beyond
/// the number of steps are empty (one frame and no step: the first range
/// holds it).
std::vector<StepRange> split_steps(std::size_t frame_count, std::size_t parts, double merge_cost = 0);

/// Scans `range` of `source` as scan_cache() would scan those frames, with
/// the sink getting the frames' positions in `source` and not the overlap
/// frame, and the totals and stage counters not counting that frame.
/// `progress` gets positions in `source` (done, source's frame count).
ScanTotals scan_range(const FrameSource& source, const StepRange& range, Backend& backend,
                      const ScanSettings& settings, ScanSink& sink, const ProgressCallback& progress = {});

}  // namespace snag::tools
