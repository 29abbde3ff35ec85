// The scan's stage counters and times as JSON, for the report's trailer
// ("stages" and "timing"; keys in man/snag-report.5).
#pragma once

#include <string>

#include "libcd/pipeline/scan.hpp"

namespace snag::tools {

/// The "stages" object: broad-phase and narrow-phase counters.
std::string stages_json(const ScanTotals& totals);
/// The "timing" object: seconds per stage, reading and writing included.
std::string timing_json(const ScanTotals& totals);
/// `timing` (a "timing" object) with "start": the seconds the tool took
/// before the scan (opening the cache, making the back end and binding it).
std::string with_start_seconds(const std::string& timing, double start_seconds);

}  // namespace snag::tools
