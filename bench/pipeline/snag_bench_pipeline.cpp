// snag-bench-pipeline: speed and accuracy of the CPU pipeline, measured in
// one run so that ratios compare like with like on a busy machine.
//   - broad phase: the VSS grid against the largest-triangle grid and brute
//     force (below --brute-force-limit triangles), CCD and static, per-stage
//     times, counts, the memory estimate and the peak RSS growth of each
//     method measured alone in a forked child (child_process.hpp);
//   - narrow phase on the CPU back end's candidates: the back end fast and
//     certified (exact certification of uncertain answers);
//   - CCD accuracy: the floating-point filter against exact CCD;
//   - static detection: the back end's intersections() against CGAL's
//     parallel self_intersections, with the pair sets compared.
// Scenes: cloth_ball92 -> 93 from --data, the bundled sample cache, and any
// --scene t0 t1. Times are medians of --repeat passes after one warm-up.
#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <exception>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "bench/pipeline/bench_scene.hpp"
#include "bench/pipeline/child_process.hpp"
#include "bench/pipeline/measurements.hpp"

namespace {

using nlohmann::json;
using snag::BroadPhaseMethod;
using snag::bench::BenchScene;
using snag::bench::ChildResult;
using snag::bench::MeasureSettings;

/// Runs `measure` in a child with the thread limit applied there (the
/// parent never starts TBB workers, so forking stays safe).
ChildResult measure_in_child(const MeasureSettings& settings, const std::function<json()>& measure) {
  return snag::bench::run_in_child([&] {
    std::unique_ptr<tbb::global_control> limit;
    if (settings.threads > 0)
      limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, settings.threads);
    return measure();
  });
}

double ratio(double x, double y) { return y > 0 ? x / y : 0.0; }

json with_rss(json value, const ChildResult& child) {
  value["peak_rss_growth_bytes"] = child.peak_rss_growth_bytes;
  value["peak_rss_reset"] = child.peak_reset;
  return value;
}

json bench_scene(const BenchScene& bench, const MeasureSettings& settings, std::size_t brute_force_limit,
                 bool static_only) {
  std::fprintf(stderr, "%s: %zu triangles, %zu vertices, %zu frames\n", bench.name.c_str(),
               bench.scene.triangle_count(), bench.scene.vertex_count(), bench.frames.size());
  json out = {{"name", bench.name},
              {"triangles", bench.scene.triangle_count()},
              {"vertices", bench.scene.vertex_count()},
              {"edges", bench.scene.edge_count()},
              {"frames", bench.frames.size()},
              {"steps", bench.steps()},
              {"broad_phase", json::array()}};
  const auto measure_static = [&] {
    std::fprintf(stderr, "  static detection against CGAL\n");
    const ChildResult child =
        measure_in_child(settings, [&] { return snag::bench::measure_static_vs_cgal(bench, settings); });
    out["static_vs_cgal"] = with_rss(child.value, child);
    return out;
  };
  if (static_only) return measure_static();
  std::vector<BroadPhaseMethod> methods = {BroadPhaseMethod::kVirtualSubdivisionGrid,
                                           BroadPhaseMethod::kLargestTriangleGrid, BroadPhaseMethod::kBoxGrid,
                                           BroadPhaseMethod::kSweepAndPrune};
  if (bench.scene.triangle_count() < brute_force_limit) methods.push_back(BroadPhaseMethod::kBruteForce);
  std::size_t vss_ccd_candidates = 0;
  for (const bool ccd : {true, false}) {
    json vss, largest;
    for (const BroadPhaseMethod method : methods) {
      std::fprintf(stderr, "  broad phase %s %s\n", ccd ? "ccd" : "static", snag::broad_phase_method_name(method));
      const ChildResult child = measure_in_child(
          settings, [&] { return snag::bench::measure_broad_phase(bench, method, ccd, settings); });
      const json result = with_rss(child.value, child);
      out["broad_phase"].push_back(result);
      if (method == BroadPhaseMethod::kVirtualSubdivisionGrid) vss = result;
      if (method == BroadPhaseMethod::kLargestTriangleGrid) largest = result;
    }
    if (ccd) vss_ccd_candidates = vss["counts"]["candidates"].get<std::size_t>();
    auto count = [](const json& r, const char* key) { return r["counts"][key].get<double>(); };
    out["vss_over_largest"][ccd ? "ccd" : "static"] = {
        {"tests", ratio(count(vss, "tests"), count(largest, "tests"))},
        {"triangle_pairs", ratio(count(vss, "triangle_pairs"), count(largest, "triangle_pairs"))},
        {"time", ratio(vss["seconds"]["total"].get<double>(), largest["seconds"]["total"].get<double>())},
        {"memory_estimate", ratio(count(vss, "memory_bytes"), count(largest, "memory_bytes"))},
        {"peak_rss_growth", ratio(vss["peak_rss_growth_bytes"].get<double>(),
                                  largest["peak_rss_growth_bytes"].get<double>())}};
  }
  std::fprintf(stderr, "  narrow phase, fast and certified\n");
  ChildResult child =
      measure_in_child(settings, [&] { return snag::bench::measure_narrow_phase(bench, settings); });
  out["narrow_phase"] = with_rss(child.value, child);
  std::fprintf(stderr, "  CCD accuracy against exact\n");
  child = measure_in_child(
      settings, [&] { return snag::bench::measure_ccd_accuracy(bench, settings, vss_ccd_candidates); });
  out["ccd_accuracy"] = child.value;
  return measure_static();
}

void print_tables(const json& report) {
  std::printf("\nbroad phase (seconds: median pass over all steps/frames; counts summed; mem: estimate / peak RSS growth)\n");
  std::printf("%-10s %-6s %-12s %2s %8s %7s %7s %7s %7s %7s | %9s %10s %11s %6s %10s %9s %9s %7s %7s\n", "scene", "mode",
              "method", "n", "total_s", "bounds", "subdiv", "regist", "pairs", "feat", "cells", "regs", "tests", "dup%",
              "tri_pairs", "VF", "EE", "est_MB", "rss_MB");
  for (const json& scene : report["scenes"]) {
    if (!scene.contains("vss_over_largest")) continue;  // --static-only
    for (const json& r : scene["broad_phase"]) {
      const json& s = r["seconds"];
      const json& c = r["counts"];
      std::printf("%-10s %-6s %-12s %2zu %8.4f %7.4f %7.4f %7.4f %7.4f %7.4f | %9zu %10zu %11zu %6.3f %10zu %9zu %9zu %7.1f %7.1f\n",
                  scene["name"].get<std::string>().c_str(), r["mode"].get<std::string>().c_str(),
                  r["method"].get<std::string>().c_str(), r["passes"].get<std::size_t>(), s["total"].get<double>(), s["bounds"].get<double>(),
                  s["subdivision"].get<double>(), s["registration"].get<double>(), s["pairs"].get<double>(),
                  s["features"].get<double>(), c["cells_used"].get<std::size_t>(),
                  c["registrations"].get<std::size_t>(), c["tests"].get<std::size_t>(),
                  c["duplicate_root_pair_percent"].get<double>(), c["triangle_pairs"].get<std::size_t>(),
                  c["vf_candidates"].get<std::size_t>(), c["ee_candidates"].get<std::size_t>(),
                  c["memory_bytes"].get<double>() / 1e6, r["peak_rss_growth_bytes"].get<double>() / 1e6);
    }
    for (const char* mode : {"ccd", "static"}) {
      const json& q = scene["vss_over_largest"][mode];
      std::printf("%-10s %-6s VSS/largest: tests %.4f, triangle pairs %.3f, time %.3f, memory est %.3f, peak RSS %.3f\n",
                  scene["name"].get<std::string>().c_str(), mode, q["tests"].get<double>(),
                  q["triangle_pairs"].get<double>(), q["time"].get<double>(), q["memory_estimate"].get<double>(),
                  q["peak_rss_growth"].get<double>());
    }
  }

  std::printf("\nnarrow phase on the CPU back end's candidates (collisions(): fast = no certifier, cert = exact certifier)\n");
  std::printf("%-10s %9s %9s %7s %9s %9s %9s | %-26s %-26s %9s %9s %9s\n", "scene", "fast_s", "cert_s", "ratio",
              "filter_s", "certify_s", "narrow_x", "VF yes/no/unc", "EE yes/no/unc", "escal%", "certified",
              "cert_true");
  for (const json& scene : report["scenes"]) {
    if (!scene.contains("narrow_phase")) continue;
    const json& n = scene["narrow_phase"];
    const json& a = n["certified"]["answers"];
    auto triple = [](const json& k) {
      return std::to_string(k["yes"].get<std::size_t>()) + "/" + std::to_string(k["no"].get<std::size_t>()) + "/" +
             std::to_string(k["uncertain"].get<std::size_t>());
    };
    std::printf("%-10s %9.4f %9.4f %7.3f %9.4f %9.4f %9.3f | %-26s %-26s %9.5f %9zu %9zu\n",
                scene["name"].get<std::string>().c_str(), n["fast"]["seconds"]["pass"].get<double>(),
                n["certified"]["seconds"]["pass"].get<double>(), n["certified_over_fast"].get<double>(),
                n["certified"]["seconds"]["ccd_filter"].get<double>(),
                n["certified"]["seconds"]["certify"].get<double>(),
                n["certified_over_fast_narrow_phase"].get<double>(), triple(a["vf"]).c_str(),
                triple(a["ee"]).c_str(), 100 * n["certified"]["escalated_fraction"].get<double>(),
                a["certified"].get<std::size_t>(), a["certified_true"].get<std::size_t>());
  }

  std::printf("\nCCD filter accuracy against exact CCD (FN: in the sample; FP and toi: over all filter yes)\n");
  std::printf("%-10s %-4s %10s %8s %9s %6s %10s %6s %6s %9s %8s %8s %9s\n", "scene", "kind", "candidates", "sampled",
              "sample_no", "FN", "filter_yes", "FP", "toi_x", "uncertain", "unc->yes", "unc->no", "us/exact");
  for (const json& scene : report["scenes"]) {
    if (!scene.contains("ccd_accuracy")) continue;
    for (const char* kind : {"vf", "ee"}) {
      const json& t = scene["ccd_accuracy"][kind];
      std::printf("%-10s %-4s %10zu %8zu %9zu %6zu %10zu %6zu %6zu %9zu %8zu %8zu %9.1f\n",
                  scene["name"].get<std::string>().c_str(), kind, t["candidates"].get<std::size_t>(),
                  t["sampled"].get<std::size_t>(), t["sampled_filter_no"].get<std::size_t>(),
                  t["false_negatives"].get<std::size_t>(), t["filter_yes"].get<std::size_t>(),
                  t["false_positives"].get<std::size_t>(), t["toi_enclosure_violations"].get<std::size_t>(),
                  t["uncertain"].get<std::size_t>(), t["uncertain_exact_yes"].get<std::size_t>(),
                  t["uncertain_exact_no"].get<std::size_t>(), t["microseconds_per_exact_query"].get<double>());
    }
  }

  std::printf("\nstatic detection: snag intersections() vs CGAL self_intersections (Parallel_if_available_tag, TBB); "
              "passes alternate; median wall s, fastest pass (min), median process CPU s; snag with its box grid, and "
              "with sweep and prune (sap_s, sap_x; sap pairs: the same as the box grid's?)\n");
  std::printf("%-10s %7s %9s %9s %8s %9s %8s %9s %9s %8s %9s %7s %10s %10s %8s %9s %s\n", "scene", "frames", "snag_s",
              "cgal_s", "speedup", "snag_min", "min_x", "snag_cpu", "cgal_cpu", "cpu_x", "sap_s", "sap_x", "snag_pairs",
              "cgal_pairs", "cgal_deg", "sap pairs", "pair sets");
  for (const json& scene : report["scenes"]) {
    const json& s = scene["static_vs_cgal"];
    std::string verdict = "identical";
    if (!s["identical"].get<bool>())
      verdict = "DIFFER: " + std::to_string(s["only_snag"].get<std::size_t>()) + " only snag, " +
                std::to_string(s["only_cgal"].get<std::size_t>()) + " only CGAL";
    if (s["cgal_mesh_repaired"].get<bool>()) verdict += " (CGAL mesh repaired: vertices split)";
    std::printf("%-10s %7zu %9.4f %9.4f %8.2f %9.4f %8.2f %9.4f %9.4f %8.2f %9.4f %7.2f %10zu %10zu %8zu %9s %s\n",
                scene["name"].get<std::string>().c_str(), s["frames"].get<std::size_t>(),
                s["snag_seconds"].get<double>(), s["cgal_seconds"].get<double>(), s["speedup"].get<double>(),
                s["snag_fastest_seconds"].get<double>(), s["speedup_fastest"].get<double>(),
                s["snag_cpu_seconds"].get<double>(), s["cgal_cpu_seconds"].get<double>(),
                s["speedup_cpu"].get<double>(), s["sweep_and_prune_seconds"].get<double>(),
                s["sweep_and_prune_speedup"].get<double>(), s["snag_pairs"].get<std::size_t>(),
                s["cgal_pairs"].get<std::size_t>(), s["cgal_degenerate_faces"].get<std::size_t>(),
                s["sweep_and_prune_frames_differing"].get<std::size_t>() == 0 ? "same" : "DIFFER", verdict.c_str());
  }

  std::printf("\nsnag static detection by stage (last pass, all frames, seconds; grid includes the vertex fans and "
              "triangle axes, found alongside the registration); "
              "how the pairs ended (every frame): fans = sharing an apart vertex, left out by the broad phase, "
              "plane = no shared vertex and b on one side of a's plane, filter = 2D exact-sign rejection, "
              "test = the exact-sign test; exact%%: predicates that needed their exact stage\n");
  std::printf("%-10s %8s %8s %8s %8s %8s %8s | %10s %7s %7s %7s %7s %10s %8s\n", "scene", "broad_s", "bounds", "grid",
              "pairs", "tests_s", "events_s", "pairs", "fans%", "plane%", "filter%", "test%", "predicates", "exact%");
  for (const json& scene : report["scenes"]) {
    const json& st = scene["static_vs_cgal"]["snag_stages"];
    const json& b = st["broad_phase"];
    const json& f = st["filter"];
    const double pairs = f["pairs"].get<double>(), fans = pairs - f["tested"].get<double>();
    const double plane = f["decided_by_plane"].get<double>(), filtered = f["decided_by_filter"].get<double>();
    const double predicates = f["axes_predicates"].get<double>() + f["plane_predicates"].get<double>() +
                              f["filter_predicates"].get<double>() + f["test_predicates"].get<double>();
    const double exact = f["axes_predicates_exact"].get<double>() + f["plane_predicates_exact"].get<double>() +
                         f["filter_predicates_exact"].get<double>() + f["test_predicates_exact"].get<double>();
    auto percent = [](double part, double whole) { return whole > 0 ? 100.0 * part / whole : 0.0; };
    std::printf("%-10s %8.4f %8.4f %8.4f %8.4f %8.4f %8.4f | %10.0f %7.2f %7.2f %7.2f %7.2f %10.0f %8.4f\n",
                scene["name"].get<std::string>().c_str(), st["broad_phase_seconds"].get<double>(),
                b["bounds"].get<double>(), b["registration"].get<double>(), b["pairs"].get<double>(),
                st["triangle_tests_seconds"].get<double>(), st["events_seconds"].get<double>(), pairs,
                percent(fans, pairs), percent(plane, pairs), percent(filtered, pairs),
                percent(pairs - fans - plane - filtered, pairs), predicates,
                percent(exact, predicates));
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Pipeline benchmark: speed and accuracy of the CPU pipeline, VSS grid vs baselines, static detection vs CGAL"};
  std::string data_dir = SNAG_SHARED_DATA_DIR, samples_dir = SNAG_SAMPLES_DIR, json_path;
  std::vector<std::vector<std::string>> extra_scenes;
  std::vector<std::string> caches;
  std::size_t sample_steps = 0, brute_force_limit = 20000;
  std::string cache_frames = "0:";
  bool no_cloth_ball = false, no_samples = false, static_only = false;
  MeasureSettings settings;
  app.add_option("--data", data_dir, "shared data directory (meshes/cloth_ball92.ply, cloth_ball93.ply)");
  app.add_option("--samples", samples_dir, "the sample cache directory (cloth.pc2, cloth_rest.obj, body.pc2, body_rest.obj)");
  app.add_option("--sample-steps", sample_steps, "steps of the sample cache to use (0 = all)");
  app.add_option("--cache-frames", cache_frames, "frames of each --cache: A:B (0-based, inclusive) or A:");
  app.add_option("--scene", extra_scenes, "another scene: two frames of one topology (t0 t1)")->expected(2);
  app.add_option("--cache", caches,
                 "another cache laid out as the sample (scripts/bake_cloth_cache.py writes one); repeatable")
      ->check(CLI::ExistingDirectory);
  app.add_flag("--no-cloth-ball", no_cloth_ball, "skip cloth_ball92 -> 93");
  app.add_flag("--no-samples", no_samples, "skip the sample cache");
  app.add_flag("--static-only", static_only, "measure static detection against CGAL alone (no broad phase, CCD or accuracy tables)");
  app.add_option("--repeat", settings.repeat, "timed passes per measurement (median), after one warm-up")
      ->check(CLI::Range(1, 1000));
  app.add_option("--slow-pass-seconds", settings.slow_pass_seconds,
                 "a measurement whose warm-up pass takes longer is timed by that pass alone");
  app.add_option("--threads", settings.threads, "worker threads (0 = all cores)");
  app.add_option("--brute-force-limit", brute_force_limit, "run brute force below this many triangles");
  app.add_option("--accuracy-sample", settings.accuracy_sample,
                 "CCD candidates checked exactly besides those the filter answered yes or uncertain");
  app.add_option("--lambda", settings.lambda, "cell size coefficient λ (> 1)");
  app.add_option("--thickness", settings.thickness, "contact distance, scene units (>= 0)");
  app.add_option("--json", json_path, "write all results as JSON");
  CLI11_PARSE(app, argc, argv);
  try {
    json report = {{"repeat", settings.repeat},
                   {"threads", settings.threads},
                   {"lambda", settings.lambda},
                   {"thickness", settings.thickness},
                   {"slow_pass_seconds", settings.slow_pass_seconds},
                   {"accuracy_sample", settings.accuracy_sample},
                   {"brute_force_limit", brute_force_limit},
                   {"peak_rss_method",
                    "each measurement in a forked child; growth = ru_maxrss after it minus ru_maxrss after "
                    "resetting the high water mark (/proc/self/clear_refs 5) at the child's start"},
                   {"scenes", json::array()}};
    if (!no_cloth_ball) {
      const std::string meshes = data_dir + "/meshes/";
      const BenchScene scene =
          snag::bench::load_mesh_pair("cloth_ball", meshes + "cloth_ball92.ply", meshes + "cloth_ball93.ply");
      report["scenes"].push_back(bench_scene(scene, settings, brute_force_limit, static_only));
    }
    if (!no_samples) {
      snag::io::FrameSelection frames;
      if (sample_steps > 0) frames.last = sample_steps;
      const BenchScene scene = snag::bench::load_sample("samples", samples_dir, frames);
      report["scenes"].push_back(bench_scene(scene, settings, brute_force_limit, static_only));
    }
    for (const std::string& dir : caches) {
      std::string name = dir;
      while (name.size() > 1 && name.back() == '/') name.pop_back();
      name = name.substr(name.find_last_of('/') + 1);
      const BenchScene scene = snag::bench::load_sample(name, dir, snag::io::parse_frame_selection(cache_frames));
      report["scenes"].push_back(bench_scene(scene, settings, brute_force_limit, static_only));
    }
    for (std::size_t i = 0; i < extra_scenes.size(); ++i) {
      const BenchScene scene = snag::bench::load_mesh_pair("scene" + std::to_string(i + 1), extra_scenes[i][0],
                                                           extra_scenes[i][1]);
      report["scenes"].push_back(bench_scene(scene, settings, brute_force_limit, static_only));
    }
    std::printf("snag-bench-pipeline: median of %d passes after one warm-up, threads %u (0 = all), λ %.2f, thickness %g\n",
                settings.repeat, settings.threads, settings.lambda, settings.thickness);
    print_tables(report);
    if (!json_path.empty()) {
      std::ofstream file(json_path);
      file << report.dump(2) << "\n";
      if (!file) throw std::runtime_error("cannot write " + json_path);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "snag-bench-pipeline: %s\n", e.what());
    return 2;
  }
  return 0;
}
