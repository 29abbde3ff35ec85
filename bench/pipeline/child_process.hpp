// Runs one measurement in a forked child process so that its peak resident
// set can be measured on its own: getrusage's ru_maxrss only ever grows, so
// within one process the second method measured would inherit the first's
// peak.
//
// How the growth is measured: the child first resets its resident-set high
// water mark (writing "5" to /proc/self/clear_refs, Linux >= 4.0), reads
// ru_maxrss as the baseline (the pages it shares copy-on-write with the
// parent count as resident), runs the measurement, and reads ru_maxrss
// again. The growth is the difference: the memory the measurement itself
// touched at its peak. Where the reset is refused the baseline is the
// parent's own high water mark at fork time, and the growth may be
// understated; `peak_reset` says which.
//
// The parent must not have started TBB worker threads before forking (a
// forked child gets none of the parent's threads); the benchmark keeps all
// parallel work inside children.
#pragma once

#include <functional>

#include <nlohmann/json.hpp>

namespace snag::bench {

struct ChildResult {
  nlohmann::json value;                    ///< what the measurement returned
  long long peak_rss_growth_bytes = 0;     ///< ru_maxrss after minus baseline, bytes
  bool peak_reset = false;                 ///< whether the high water mark was reset first
};

/// Runs `measure` in a forked child and returns its JSON result and the
/// child's peak RSS growth. Throws std::runtime_error when the child fails
/// (its exception message is passed back) or cannot be started.
ChildResult run_in_child(const std::function<nlohmann::json()>& measure);

}  // namespace snag::bench
