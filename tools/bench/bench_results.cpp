#include "tools/bench/bench_results.hpp"

namespace snag::bench {

namespace {

using nlohmann::json;

double micros_per_query(const MethodCounts& counts, std::size_t queries) {
  return queries == 0 ? 0.0 : counts.seconds * 1e6 / double(queries);
}

json method_counts_json(const AllMethodCounts& all, std::size_t queries) {
  json out = json::object();
  for (CcdMethod method : kCcdMethods) {
    const MethodCounts& c = all[static_cast<int>(method)];
    out[method_id(method)] = {{"fn", c.false_negatives},
                              {"fp", c.false_positives},
                              {"uncertain", c.uncertain},
                              {"us_per_query", micros_per_query(c, queries)}};
  }
  return out;
}

json query_set_json(const QuerySetBenchmark& set) {
  return {{"name", set.name},
          {"kind", set.edge_edge ? "ee" : "vf"},
          {"queries", set.queries},
          {"positives", set.positives},
          {"methods", method_counts_json(set.methods, set.queries)}};
}

/// Per kind, the sum of every query set of that kind (named "all").
std::vector<QuerySetBenchmark> query_totals(const std::vector<QuerySetBenchmark>& sets) {
  std::vector<QuerySetBenchmark> totals;
  for (bool edge_edge : {false, true}) {
    QuerySetBenchmark total;
    total.name = "all";
    total.edge_edge = edge_edge;
    for (const QuerySetBenchmark& set : sets) {
      if (set.edge_edge != edge_edge) continue;
      total.queries += set.queries;
      total.positives += set.positives;
      for (int m = 0; m < kCcdMethodCount; ++m) {
        total.methods[m].false_negatives += set.methods[m].false_negatives;
        total.methods[m].false_positives += set.methods[m].false_positives;
        total.methods[m].uncertain += set.methods[m].uncertain;
        total.methods[m].seconds += set.methods[m].seconds;
      }
    }
    if (total.queries > 0) totals.push_back(total);
  }
  return totals;
}

json family_json(const FamilyBenchmark& f) {
  json methods = json::object();
  for (CcdMethod method : kCcdMethods) {
    json fn = json::array(), fp = json::array(), uncertain = json::array(), errors = json::array();
    for (const AllMethodCounts& at : f.methods) {
      const MethodCounts& c = at[static_cast<int>(method)];
      fn.push_back(c.false_negatives);
      fp.push_back(c.false_positives);
      uncertain.push_back(c.uncertain);
      errors.push_back(double(c.false_negatives + c.false_positives) / f.samples);
    }
    methods[method_id(method)] = {{"fn", fn}, {"fp", fp}, {"uncertain", uncertain}, {"error_rate", errors}};
  }
  return {{"name", f.family.name},       {"kind", f.family.edge_edge ? "ee" : "vf"},
          {"knob", f.family.knob},       {"description", f.family.description},
          {"samples", f.samples},        {"knob_values", f.family.knob_values},
          {"positives", f.positives},    {"methods", methods}};
}

json broad_phase_json(const BroadPhaseRun& run) {
  return {{"name", run.name},
          {"method", run.method},
          {"lambda", run.lambda},
          {"max_subdivision_levels", run.max_subdivision_levels},
          {"max_time_halvings", run.max_time_halvings},
          {"skipped", run.skipped},
          {"tests", run.tests},
          {"candidates", run.candidates},
          {"cells_used", run.cells_used},
          {"levels_used", run.levels_used},
          {"time_halvings", run.time_halvings},
          {"triangles_subdivided", run.triangles_subdivided},
          {"memory_bytes", run.memory_bytes},
          {"seconds", run.seconds},
          {"missed", run.missed}};
}

json scene_json(const SceneBenchmark& s) {
  json tiers = json::object();
  for (int t = 0; t < kCcdTierCount; ++t) tiers[tier_id(static_cast<CcdTier>(t))] = s.tiers[t];
  json broad = json::array();
  for (const BroadPhaseRun& run : s.broad_phases) broad.push_back(broad_phase_json(run));
  return {{"name", s.name},
          {"description", s.description},
          {"steps", s.steps},
          {"vertices", s.vertices},
          {"triangles", s.triangles},
          {"positives", s.positives},
          {"vf_candidates", s.vf_candidates},
          {"ee_candidates", s.ee_candidates},
          {"tiers", tiers},
          {"adaptive",
           {{"candidates", s.grid_candidates},
            {"exact_queries", s.tiers[static_cast<int>(CcdTier::kExact)]},
            {"broad_seconds", s.adaptive_broad_seconds},
            {"narrow_seconds", s.adaptive_narrow_seconds}}},
          {"heavy",
           {{"candidates", s.complete_candidates},
            {"exact_queries", s.complete_candidates},
            {"broad_seconds", s.heavy_broad_seconds},
            {"narrow_seconds", s.heavy_narrow_seconds}}},
          {"same_answers", s.same_answers},
          {"methods", method_counts_json(s.methods, s.grid_candidates)},
          {"broad_phases", broad}};
}

bool exact_and_certified_clean(const AllMethodCounts& all) {
  for (CcdMethod method : {CcdMethod::kCertified, CcdMethod::kExact}) {
    const MethodCounts& c = all[static_cast<int>(method)];
    if (c.false_negatives + c.false_positives + c.uncertain > 0) return false;
  }
  return true;
}

void print_counts_row(std::FILE* out, const std::string& set, const char* kind, const AllMethodCounts& all,
                      std::size_t queries) {
  for (CcdMethod method : kCcdMethods) {
    const MethodCounts& c = all[static_cast<int>(method)];
    std::fprintf(out, "%-36s %-3s %-13s %7zu %7zu %7zu %9zu %11.2f\n", set.c_str(), kind, method_id(method), queries,
                 c.false_negatives, c.false_positives, c.uncertain, micros_per_query(c, queries));
  }
}

}  // namespace

json bench_json(const BenchResults& results) {
  json methods = json::array();
  for (CcdMethod method : kCcdMethods) methods.push_back({{"id", method_id(method)}, {"label", method_label(method)}});
  json tiers = json::array();
  for (int t = 0; t < kCcdTierCount; ++t) tiers.push_back(tier_id(static_cast<CcdTier>(t)));
  json sets = json::array(), totals = json::array(), families = json::array(), scenes = json::array();
  for (const QuerySetBenchmark& set : results.query_sets) sets.push_back(query_set_json(set));
  for (const QuerySetBenchmark& total : query_totals(results.query_sets)) totals.push_back(query_set_json(total));
  for (const FamilyBenchmark& family : results.families) families.push_back(family_json(family));
  for (const SceneBenchmark& scene : results.scenes) scenes.push_back(scene_json(scene));
  return {{"snag_bench", 1},          {"quick", results.quick},   {"repeats", results.repeats},
          {"threads", results.threads}, {"methods", methods},     {"tiers", tiers},
          {"query_sets", sets},       {"query_totals", totals},   {"families", families},
          {"scenes", scenes},         {"exact_methods_agree", exact_methods_agree(results)}};
}

bool exact_methods_agree(const BenchResults& results) {
  for (const QuerySetBenchmark& set : results.query_sets)
    if (!exact_and_certified_clean(set.methods)) return false;
  for (const FamilyBenchmark& family : results.families)
    for (const AllMethodCounts& at : family.methods)
      if (!exact_and_certified_clean(at)) return false;
  for (const SceneBenchmark& scene : results.scenes)
    if (!exact_and_certified_clean(scene.methods) || !scene.same_answers) return false;
  return true;
}

void print_bench_summary(std::FILE* out, const BenchResults& results) {
  if (!results.query_sets.empty() || !results.scenes.empty()) {
    std::fprintf(out, "%-36s %-3s %-13s %7s %7s %7s %9s %11s\n", "data set", "kind", "method", "queries", "FN", "FP",
                 "uncertain", "us/query");
  }
  for (const QuerySetBenchmark& set : results.query_sets)
    print_counts_row(out, set.name, set.edge_edge ? "ee" : "vf", set.methods, set.queries);
  for (const QuerySetBenchmark& total : query_totals(results.query_sets))
    print_counts_row(out, "all query sets", total.edge_edge ? "ee" : "vf", total.methods, total.queries);
  for (const SceneBenchmark& scene : results.scenes)
    print_counts_row(out, scene.name + " (grid candidates)", "all", scene.methods, scene.grid_candidates);

  if (!results.families.empty()) {
    std::fprintf(out, "\nstability families (%d samples per knob value): the knob values where a method erred\n",
                 results.families.front().samples);
    for (const FamilyBenchmark& f : results.families) {
      std::fprintf(out, "  %-15s %-9s", f.family.name.c_str(), f.family.knob.c_str());
      for (CcdMethod method : kCcdMethods) {
        std::size_t erring = 0;
        for (const AllMethodCounts& at : f.methods) {
          const MethodCounts& c = at[static_cast<int>(method)];
          erring += c.false_negatives + c.false_positives > 0;
        }
        std::fprintf(out, " %s %zu/%zu", method_id(method), erring, f.methods.size());
      }
      std::fprintf(out, "\n");
    }
  }

  for (const SceneBenchmark& s : results.scenes) {
    std::fprintf(out, "\nscene %s: %zu steps, %zu triangles, %zu colliding pairs (exact)\n", s.name.c_str(), s.steps,
                 s.triangles, s.positives);
    std::fprintf(out, "  adaptive: %zu grid candidates, decided by", s.grid_candidates);
    for (int t = 0; t < kCcdTierCount; ++t) std::fprintf(out, " %s %zu", tier_id(static_cast<CcdTier>(t)), s.tiers[t]);
    std::fprintf(out, "; %.3f s broad + %.3f s narrow\n", s.adaptive_broad_seconds, s.adaptive_narrow_seconds);
    std::fprintf(out, "  heavy:    %zu complete candidates, all exact; %.3f s broad + %.3f s narrow\n",
                 s.complete_candidates, s.heavy_broad_seconds, s.heavy_narrow_seconds);
    std::fprintf(out, "  same answers: %s\n", s.same_answers ? "yes" : "NO");
    std::fprintf(out, "  %-30s %12s %11s %8s %7s %9s %12s %9s %6s\n", "broad phase", "tests", "candidates", "cells",
                 "levels", "halvings", "memory (B)", "seconds", "missed");
    for (const BroadPhaseRun& run : s.broad_phases) {
      if (run.skipped) {
        std::fprintf(out, "  %-30s skipped (more than --brute-force-max-triangles)\n", run.name.c_str());
        continue;
      }
      std::fprintf(out, "  %-30s %12zu %11zu %8zu %7zu %9zu %12zu %9.4f %6zu\n", run.name.c_str(), run.tests,
                   run.candidates, run.cells_used, run.levels_used, run.time_halvings, run.memory_bytes, run.seconds,
                   run.missed);
    }
  }
}

}  // namespace snag::bench
