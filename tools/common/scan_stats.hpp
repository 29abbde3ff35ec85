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

}  // namespace snag::tools
