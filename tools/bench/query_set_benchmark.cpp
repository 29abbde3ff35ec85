#include "tools/bench/query_set_benchmark.hpp"

#include <filesystem>
#include <map>
#include <utility>

#include "io/ccd_query_csv.hpp"
#include "libcd/core/error.hpp"

namespace snag::bench {

std::vector<QuerySetBenchmark> benchmark_query_sets(const std::string& root, int repeats) {
  const std::vector<io::CcdQuery> queries = io::read_ccd_query_tree(root);
  if (queries.empty())
    throw UsageError("--queries " + root + ": no query files (*.csv in vertex-face/ or edge-edge/ folders)");
  std::map<std::pair<std::string, bool>, std::vector<LabelledQuery>> sets;
  for (const io::CcdQuery& q : queries) {
    const std::string set = std::filesystem::path(q.file).parent_path().parent_path().filename().string();
    sets[{set, q.is_edge_edge}].push_back({{q.is_edge_edge, q.points}, q.truth});
  }
  std::vector<QuerySetBenchmark> out;
  for (const auto& [key, labelled] : sets) {
    QuerySetBenchmark result;
    result.name = key.first;
    result.edge_edge = key.second;
    result.queries = labelled.size();
    for (const LabelledQuery& q : labelled) result.positives += q.truth;
    result.methods = count_methods(labelled, repeats);
    out.push_back(std::move(result));
  }
  return out;
}

}  // namespace snag::bench
