// Everything one snag-bench run measured, its JSON (the input of
// exporters/bench_page.hpp) and the table it prints.
#pragma once

#include <cstdio>
#include <nlohmann/json.hpp>
#include <vector>

#include "tools/bench/family_benchmark.hpp"
#include "tools/bench/query_set_benchmark.hpp"
#include "tools/bench/scene_benchmark.hpp"

namespace snag::bench {

struct BenchResults {
  bool quick = false;
  int repeats = 0;
  unsigned threads = 0;
  std::vector<QuerySetBenchmark> query_sets;
  std::vector<FamilyBenchmark> families;
  std::vector<SceneBenchmark> scenes;
};

/// The results as JSON (layout in man/snag-bench.1): every count, times in
/// microseconds per query, and per query kind the sums over all query sets
/// ("query_totals").
nlohmann::json bench_json(const BenchResults& results);

/// The table a person reads: per data set and kind, each method's false
/// negatives, false positives, uncertain answers and microseconds per query;
/// then per family the knob value where each method first errs; then per
/// scene the tiers, the work saved and the broad phases.
void print_bench_summary(std::FILE* out, const BenchResults& results);

/// True when the exact and the certified methods made no error anywhere
/// (query sets, families, scenes) and every scene's adaptive run found the
/// ground truth: snag-bench's exit status 0.
bool exact_methods_agree(const BenchResults& results);

}  // namespace snag::bench
