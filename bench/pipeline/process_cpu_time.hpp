// The CPU time of the whole process (every thread), for measurements on a
// machine that other work shares: wall time grows with the other work's
// share of the cores, CPU time much less. TBB workers that spin while they
// wait count too, alike for snag and CGAL (both run on TBB).
#pragma once

#include <time.h>

namespace snag::bench {

/// Seconds of CPU time the process has used so far (CLOCK_PROCESS_CPUTIME_ID).
inline double process_cpu_seconds() {
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return double(now.tv_sec) + 1e-9 * double(now.tv_nsec);
}

}  // namespace snag::bench
