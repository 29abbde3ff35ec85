// Every CCD method on the stability families of stability_families.hpp,
// along each family's knob.
#pragma once

#include <vector>

#include "tools/bench/stability_families.hpp"

namespace snag::bench {

struct FamilyBenchmark {
  StabilityFamily family;
  int samples = 0;                         ///< queries per knob value
  std::vector<std::size_t> positives;      ///< per knob value: samples that collide (exact)
  std::vector<AllMethodCounts> methods;    ///< per knob value (answers only, not timed)
};

/// Runs the families named in `names` (all when empty), in the order of
/// stability_families(), with `samples` queries per knob value (> 0), seeded
/// so that a run is reproducible. Throws UsageError naming an unknown family.
std::vector<FamilyBenchmark> benchmark_families(int samples, const std::vector<std::string>& names = {});

}  // namespace snag::bench
