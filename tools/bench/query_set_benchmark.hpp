// Every CCD method on query sets with exact ground truth (the CSV format of
// io/ccd_query_csv.hpp), per data set (the folder holding vertex-face/ and
// edge-edge/) and kind.
#pragma once

#include <string>
#include <vector>

#include "tools/bench/method_counts.hpp"

namespace snag::bench {

struct QuerySetBenchmark {
  std::string name;  ///< the data set's folder name, e.g. "erleben-spikes"
  bool edge_edge = false;
  std::size_t queries = 0, positives = 0;
  AllMethodCounts methods{};
};

/// Reads every query under `root` (io::read_ccd_query_tree) and runs every
/// method on each data set and kind, in sorted order; `repeats` timed passes.
/// Throws InputError for a bad file and UsageError when `root` holds no query.
std::vector<QuerySetBenchmark> benchmark_query_sets(const std::string& root, int repeats);

}  // namespace snag::bench
