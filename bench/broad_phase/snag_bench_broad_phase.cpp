// snag-bench-broad-phase: the VSS grid against the largest-triangle grid and
// brute force, on a pair of frames (default cloth_ball92 -> 93), for CCD and
// static detection. Prints a table of median stage times and counts and, with
// --json, writes them. Brute force runs below 20,000 triangles or with
// --brute-force.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "bench/broad_phase/binary_ply.hpp"
#include "libcd/broad_phase/broad_phase.hpp"

namespace {

using snag::BroadPhaseMethod;
using snag::BroadPhaseStats;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

struct Result {
  std::string mode, method;
  BroadPhaseStats stats;  // of the last run (counts do not vary)
  double total = 0, bounds = 0, subdivision = 0, registration = 0, pairs = 0, features = 0;  // medians, seconds
};

/// Root-pair tests repeated (kept or culled by the DOPs), in percent of all tests.
double duplicate_percent(const BroadPhaseStats& s) {
  return s.tests ? 100.0 * double(s.duplicate_root_pair_tests + s.duplicate_culled_tests) / double(s.tests) : 0;
}

nlohmann::json to_json(const Result& r) {
  const BroadPhaseStats& s = r.stats;
  const double dup_pct = duplicate_percent(s);
  return {{"mode", r.mode}, {"method", r.method},
          {"seconds", {{"total", r.total}, {"bounds", r.bounds}, {"subdivision", r.subdivision},
                       {"registration", r.registration}, {"pairs", r.pairs}, {"features", r.features}}},
          {"cell_size", s.cell_size}, {"grid_dims", {s.grid_dims[0], s.grid_dims[1], s.grid_dims[2]}},
          {"cells_used", s.cells_used}, {"root_triangles", s.root_triangles},
          {"triangles_subdivided", s.triangles_subdivided}, {"time_halvings", s.time_halvings},
          {"levels", s.triangles_per_level.size()}, {"triangles_per_level", s.triangles_per_level},
          {"oversized_leaves", s.oversized_leaves}, {"leaf_triangles", s.leaf_triangles},
          {"registrations", s.registrations}, {"home_registrations", s.home_registrations},
          {"phantom_registrations", s.phantom_registrations},
          {"duplicate_registrations_removed", s.duplicate_registrations_removed}, {"tests", s.tests},
          {"culled_by_boxes", s.culled_by_boxes},
          {"same_root_tests", s.same_root_tests}, {"removed_by_time_slots", s.removed_by_time_slots},
          {"removed_by_control_bits", s.removed_by_control_bits},
          {"removed_by_extended_control_bits", s.removed_by_extended_control_bits},
          {"fallback_tests", s.fallback_tests}, {"tests_after_control_bits", s.tests_after_control_bits},
          {"duplicate_root_pair_tests", s.duplicate_root_pair_tests},
          {"duplicate_culled_tests", s.duplicate_culled_tests}, {"duplicate_root_pair_percent", dup_pct},
          {"culled_by_dop", s.culled_by_dop}, {"triangle_pairs", s.triangle_pairs},
          {"separated_triangle_pairs", s.separated_triangle_pairs},
          {"vf_before_culling", s.vf_before_culling}, {"vf_after_culling", s.vf_after_culling},
          {"ee_before_culling", s.ee_before_culling}, {"ee_after_culling", s.ee_after_culling},
          {"candidates", s.candidates}, {"memory_bytes", s.memory_bytes}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Broad phase benchmark: VSS grid vs largest-triangle grid vs brute force"};
  const std::string meshes = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/";
  std::string t0 = meshes + "cloth_ball92.ply", t1 = meshes + "cloth_ball93.ply", json_path;
  int runs = 3;
  bool brute = false;
  snag::BroadPhaseSettings settings;
  settings.count_culled_duplicates = true;  // the chapter's duplicate-test claim counts every test
  app.add_option("--t0", t0, "binary PLY of the first frame");
  app.add_option("--t1", t1, "binary PLY of the second frame (same topology)");
  app.add_option("--runs", runs, "runs per measurement; the median is reported")->check(CLI::Range(1, 1000));
  app.add_flag("--brute-force", brute, "run brute force even above 20,000 triangles");
  app.add_option("--lambda", settings.lambda, "cell size coefficient λ (> 1)");
  app.add_option("--thickness", settings.thickness, "thickness, scene units");
  app.add_option("--threads", settings.threads, "worker threads (0 = all)");
  app.add_option("--json", json_path, "write the results as JSON");
  CLI11_PARSE(app, argc, argv);
  try {
    const snag::bench::PlyMesh a = snag::bench::read_binary_ply(t0);
    const snag::bench::PlyMesh b = snag::bench::read_binary_ply(t1);
    if (a.vertices.size() != b.vertices.size()) throw std::runtime_error("the two frames differ in vertex count");
    const snag::Scene scene({snag::make_object("mesh", static_cast<snag::Index>(a.vertices.size()), a.triangles)});
    std::vector<BroadPhaseMethod> methods = {BroadPhaseMethod::kVirtualSubdivisionGrid,
                                             BroadPhaseMethod::kLargestTriangleGrid};
    if (brute || scene.triangle_count() < 20000) methods.push_back(BroadPhaseMethod::kBruteForce);

    std::vector<Result> results;
    for (const char* mode : {"ccd", "static"}) {
      for (BroadPhaseMethod method : methods) {
        auto phase = snag::make_broad_phase(method);
        phase->build(scene, settings);
        Result r{mode, broad_phase_method_name(method), {}};
        std::vector<double> total, bounds, subdivision, registration, pairs, features;
        for (int k = 0; k < runs; ++k) {
          if (std::string(mode) == "ccd") {
            std::vector<snag::VertexFaceCandidate> vf;
            std::vector<snag::EdgeEdgeCandidate> ee;
            phase->detect_ccd(a.vertices, b.vertices, vf, ee);
          } else {
            std::vector<snag::TrianglePair> tp;
            phase->detect_static(a.vertices, tp);
          }
          const BroadPhaseStats& s = phase->stats();
          total.push_back(s.seconds_total);
          bounds.push_back(s.seconds_bounds);
          subdivision.push_back(s.seconds_subdivision);
          registration.push_back(s.seconds_registration);
          pairs.push_back(s.seconds_pairs);
          features.push_back(s.seconds_features);
        }
        r.stats = phase->stats();
        r.total = median(total), r.bounds = median(bounds), r.subdivision = median(subdivision);
        r.registration = median(registration), r.pairs = median(pairs), r.features = median(features);
        results.push_back(r);
      }
    }

    std::printf("%s -> %s: %zu triangles, %zu vertices, median of %d runs\n", t0.c_str(), t1.c_str(),
                scene.triangle_count(), scene.vertex_count(), runs);
    std::printf("%-6s %-12s %8s %8s %8s %8s %8s | %6s %9s %9s %11s %11s %7s %10s %10s %10s %8s\n", "mode", "method",
                "total_s", "subdiv", "regist", "pairs", "feat", "levels", "leaves", "cells", "regs", "tests",
                "dup%", "tri_pairs", "candidates", "ctrl_bits", "mem_MB");
    for (const Result& r : results) {
      const BroadPhaseStats& s = r.stats;
      std::printf("%-6s %-12s %8.4f %8.4f %8.4f %8.4f %8.4f | %6zu %9zu %9zu %11zu %11zu %7.3f %10zu %10zu %10zu %8.1f\n",
                  r.mode.c_str(), r.method.c_str(), r.total, r.subdivision, r.registration, r.pairs, r.features,
                  s.triangles_per_level.size(), s.leaf_triangles, s.cells_used, s.registrations, s.tests,
                  duplicate_percent(s), s.triangle_pairs,
                  s.candidates, s.removed_by_control_bits + s.removed_by_extended_control_bits,
                  double(s.memory_bytes) / 1e6);
    }
    nlohmann::json out = {{"t0", t0}, {"t1", t1}, {"runs", runs}, {"results", nlohmann::json::array()},
                          {"ratios_vss_over_largest", nlohmann::json::object()}};
    for (const Result& r : results) out["results"].push_back(to_json(r));
    for (const char* mode : {"ccd", "static"}) {
      const Result *v = nullptr, *l = nullptr;
      for (const Result& r : results) {
        if (r.mode != mode) continue;
        if (r.method == "vss-grid") v = &r;
        if (r.method == "largest-grid") l = &r;
      }
      if (v == nullptr || l == nullptr) continue;
      auto ratio = [](double x, double y) { return y > 0 ? x / y : 0.0; };
      const nlohmann::json ratios = {
          {"time", ratio(v->total, l->total)},
          {"tests", ratio(double(v->stats.tests), double(l->stats.tests))},
          {"triangle_pairs", ratio(double(v->stats.triangle_pairs), double(l->stats.triangle_pairs))},
          {"memory", ratio(double(v->stats.memory_bytes), double(l->stats.memory_bytes))}};
      out["ratios_vss_over_largest"][mode] = ratios;
      std::printf("%s VSS/largest: time %.3f, tests %.4f, triangle pairs %.3f, memory %.3f\n", mode,
                  ratios["time"].get<double>(), ratios["tests"].get<double>(), ratios["triangle_pairs"].get<double>(),
                  ratios["memory"].get<double>());
    }
    if (!json_path.empty()) {
      std::ofstream file(json_path);
      file << out.dump(2) << "\n";
      if (!file) throw std::runtime_error("cannot write " + json_path);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "snag-bench-broad-phase: %s\n", e.what());
    return 2;
  }
  return 0;
}
