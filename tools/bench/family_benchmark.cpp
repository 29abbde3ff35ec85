#include "tools/bench/family_benchmark.hpp"

#include <algorithm>

#include "libcd/core/error.hpp"

namespace snag::bench {

std::vector<FamilyBenchmark> benchmark_families(int samples, const std::vector<std::string>& names) {
  const std::vector<StabilityFamily> families = stability_families();
  for (const std::string& name : names) {
    if (std::none_of(families.begin(), families.end(), [&](const StabilityFamily& f) { return f.name == name; })) {
      std::string known;
      for (const StabilityFamily& f : families) known += (known.empty() ? "" : ", ") + f.name;
      throw UsageError("--families: no family named '" + name + "' (known: " + known + ")");
    }
  }
  std::vector<FamilyBenchmark> out;
  std::uint64_t seed = 0;
  for (const StabilityFamily& family : families) {
    seed += family.knob_values.size();  // each family's seeds stay the same whichever run
    if (!names.empty() && std::find(names.begin(), names.end(), family.name) == names.end()) continue;
    std::uint64_t knob_seed = seed;
    FamilyBenchmark result;
    result.family = family;
    result.samples = samples;
    for (double knob : family.knob_values) {
      const std::vector<LabelledQuery> queries = family_queries(family, knob, samples, knob_seed++);
      std::size_t positives = 0;
      for (const LabelledQuery& q : queries) positives += q.truth;
      result.positives.push_back(positives);
      result.methods.push_back(count_methods(queries, 0));
    }
    out.push_back(std::move(result));
  }
  return out;
}

}  // namespace snag::bench
