// Confusion counts and time of every CCD method of ccd_methods.hpp on a list
// of queries whose ground truth is known: one query set, one knob value of a
// stability family, or one scene's candidates.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "tools/bench/ccd_methods.hpp"

namespace snag::bench {

/// A query with its ground truth (true: the pair touches at some t in [0, 1]).
struct LabelledQuery {
  CcdQueryPoints query;
  bool truth = false;
};

/// What one method answered on a list of queries.
struct MethodCounts {
  std::size_t false_negatives = 0;  ///< answered no, truth yes
  std::size_t false_positives = 0;  ///< answered yes, truth no
  std::size_t uncertain = 0;        ///< answered neither (the filter alone)
  double seconds = 0;               ///< fastest of the timed passes over all queries (0 when not timed)
};

/// Counts of every method, indexed by CcdMethod.
using AllMethodCounts = std::array<MethodCounts, kCcdMethodCount>;

/// Runs every method over `queries`; the time of a method is the fastest of
/// `repeats` passes (>= 1; 0: answers only, no timing). One thread.
/// Throws what run_ccd_method throws.
AllMethodCounts count_methods(const std::vector<LabelledQuery>& queries, int repeats);

}  // namespace snag::bench
