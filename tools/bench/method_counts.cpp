#include "tools/bench/method_counts.hpp"

#include <algorithm>
#include <chrono>

namespace snag::bench {

AllMethodCounts count_methods(const std::vector<LabelledQuery>& queries, int repeats) {
  using Clock = std::chrono::steady_clock;
  AllMethodCounts all;
  for (CcdMethod method : kCcdMethods) {
    MethodCounts& counts = all[static_cast<int>(method)];
    for (const LabelledQuery& q : queries) {
      switch (run_ccd_method(method, q.query)) {
        case CcdVerdict::kYes: counts.false_positives += !q.truth; break;
        case CcdVerdict::kNo: counts.false_negatives += q.truth; break;
        case CcdVerdict::kUncertain: ++counts.uncertain; break;
      }
    }
    // Timed apart from the counting pass, so that counting costs nothing; the
    // answers go to a volatile sink so that the calls cannot be dropped.
    static volatile std::size_t sink = 0;
    for (int pass = 0; pass < repeats; ++pass) {
      std::size_t yes = 0;
      const auto start = Clock::now();
      for (const LabelledQuery& q : queries) yes += run_ccd_method(method, q.query) == CcdVerdict::kYes;
      const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
      sink = sink + yes;
      counts.seconds = pass == 0 ? seconds : std::min(counts.seconds, seconds);
    }
  }
  return all;
}

}  // namespace snag::bench
