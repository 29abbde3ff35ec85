// The "stages" and "timing" objects of a scan split into ranges (see
// range_scan.hpp), joined into the ones a single scan of all the frames
// writes: counters add up, the grid and cell size are the last range's
// (a scan keeps its last step's), peaks and level counts are the largest,
// and ratios are worked out again from the joined counters.
#pragma once

#include <string>
#include <vector>

namespace snag::tools {

/// Joins the ranges' stages objects (scan_stats.hpp's stages_json), in range
/// order, as text. Throws std::invalid_argument on text that is not such an object.
std::string merge_stages_json(const std::vector<std::string>& ranges);

/// Joins the ranges' timing objects: each time is the sum over the ranges
/// (CPU-seconds), except "total", which is `total_seconds` (the run's wall time).
std::string merge_timing_json(const std::vector<std::string>& ranges, double total_seconds);

}  // namespace snag::tools
