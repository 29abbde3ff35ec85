// snag-bench-gpu: the CUDA back end against the CPU back end on real cloth.
//  1. cloth_ball92 -> 93: collisions of the step and intersections of frame
//     93 per run, median of --runs runs after warm-up, per stage (broad phases
//     from their stats, narrow CCD, certification, static), candidate
//     counts, peak device memory; the CPU back end in the same run (ratio);
//     the GPU back end with the virtual subdivision grid and with the
//     largest-triangle grid.
//  2. The narrow phase alone on the step's candidates, timed with CUDA
//     events: screen then search against a single pass; tests per second.
//  3. Scaling: the cloth Loop-subdivided twice (16 times the triangles, both
//     frames refined alike), over the whole step, where each triangle now
//     moves 4 times its size as far, and over the first quarter of the step
//     (x_t1 = x_t0 + (x_t1 - x_t0) / 4, on the linear trajectories), where
//     motion per triangle size is the original's, as a simulation at this
//     resolution would take it. The CPU back end runs the quarter step
//     --large-cpu-runs times.
//  4. The sample cache end to end through scan_cache (reading included):
//     frames per second.
// Prints a table last; --json FILE (or --benchmark_out=FILE) writes the results.
// --write-refined DIR only writes the refined cloth's frames (Loop-subdivided
// once and twice, the whole step) as PLY files for the end-to-end benchmark
// (bench/scan/scan_bench.py) and exits.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "bench/broad_phase/binary_ply.hpp"
#include "bench/gpu/loop_subdivision.hpp"
#include "bench/gpu/write_ply.hpp"
#include "io/open_cache.hpp"
#include "libcd/cuda/cuda_backend.hpp"
#include "libcd/cuda/cuda_broad_phase.cuh"
#include "libcd/cuda/cuda_error.hpp"
#include "libcd/cuda/device.hpp"
#include "libcd/cuda/device_memory_tracker.hpp"
#include "bench/gpu/narrow_phase_benchmark.hpp"
#include "libcd/pipeline/scan.hpp"
#include "snag/config.hpp"
#if SNAG_HAVE_CGAL
#include "validate/exact_certifier.hpp"
#endif

namespace snag {
namespace {

using Clock = std::chrono::steady_clock;
using json = nlohmann::json;

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

struct Options {
  std::string json_path;
  std::string refined_dir;  ///< --write-refined: write the refined frames here and stop
  bool memory_census = false;  ///< --memory-census: the broad phase's buffers on the refined cloth, and stop
  std::string data_dir = SNAG_SHARED_DATA_DIR;
  std::string samples_dir = std::string(SNAG_SOURCE_DIR) + "/samples";
  int runs = 20, warmup = 2, large_runs = 5, large_cpu_runs = 1;
  bool large = true, cpu = true;
};

/// Medians of one back end on one step, milliseconds.
struct StepTimes {
  std::string backend, broad_phase;
  double total_ms = 0, ccd_broad_ms = 0, narrow_ccd_ms = 0, certify_ms = 0, static_broad_ms = 0, static_ms = 0;
  double bounds_ms = 0, subdivision_ms = 0, registration_ms = 0, pairs_ms = 0, features_ms = 0;
  double ccd_device_ms = 0, ccd_events_ms = 0, static_device_ms = 0, static_events_ms = 0;
  std::size_t vf = 0, ee = 0, pairs = 0, collisions = 0, intersections = 0, grid_tests = 0;
  std::size_t peak_device_bytes = 0, broad_memory_bytes = 0;
  int runs = 0;
  json to_json() const {
    return {{"backend", backend},
            {"broad_phase", broad_phase},
            {"runs", runs},
            {"total_ms", total_ms},
            {"ccd_broad_ms", ccd_broad_ms},
            {"ccd_broad_stages_ms",
             {{"bounds", bounds_ms},
              {"subdivision", subdivision_ms},
              {"registration", registration_ms},
              {"pairs", pairs_ms},
              {"features", features_ms}}},
            {"narrow_ccd_ms", narrow_ccd_ms},
            {"narrow_ccd_parts_ms", {{"device", ccd_device_ms}, {"events", ccd_events_ms}}},
            {"certify_ms", certify_ms},
            {"static_broad_ms", static_broad_ms},
            {"static_narrow_ms", static_ms},
            {"static_narrow_parts_ms", {{"device", static_device_ms}, {"events", static_events_ms}}},
            {"vf_candidates", vf},
            {"ee_candidates", ee},
            {"triangle_pairs", pairs},
            {"grid_tests", grid_tests},
            {"collisions", collisions},
            {"intersections", intersections},
            {"peak_device_bytes", peak_device_bytes},
            {"broad_memory_bytes", broad_memory_bytes}};
  }
};

/// Runs collisions(x_t0, x_t1) and intersections(x_t1) `runs` times after
/// `warmup` runs and keeps the medians.
StepTimes time_step(Backend& backend, const std::string& broad_name, const Scene& scene,
                    const BackendSettings& settings, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                    int warmup, int runs) {
  DeviceMemoryTracker::instance().reset_peak();
  backend.bind(scene, settings);
  std::vector<double> total, ccd_broad, narrow, certify, static_broad, static_narrow, bounds, subdivision,
      registration, pairs, features, ccd_device, ccd_events, static_device, static_events;
  StepTimes times;
  times.backend = backend.name();
  times.broad_phase = broad_name;
  times.runs = runs;
  std::vector<Event> events;  // reused, as scan_cache reuses its own
  for (int run = 0; run < warmup + runs; ++run) {
    events.clear();
    const auto start = Clock::now();
    backend.collisions(x_t0, x_t1, events);
    const PipelineStats ccd = backend.stats();
    const std::size_t collisions = events.size();
    backend.intersections(x_t1, events);
    const PipelineStats dcd = backend.stats();
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    if (run < warmup) continue;
    total.push_back(ms);
    ccd_broad.push_back(1e3 * ccd.ccd_broad.seconds_total);
    bounds.push_back(1e3 * ccd.ccd_broad.seconds_bounds);
    subdivision.push_back(1e3 * ccd.ccd_broad.seconds_subdivision);
    registration.push_back(1e3 * ccd.ccd_broad.seconds_registration);
    pairs.push_back(1e3 * ccd.ccd_broad.seconds_pairs);
    features.push_back(1e3 * ccd.ccd_broad.seconds_features);
    narrow.push_back(1e3 * ccd.narrow.seconds_ccd);
    certify.push_back(1e3 * ccd.narrow.seconds_certify);
    static_broad.push_back(1e3 * dcd.static_broad.seconds_total);
    static_narrow.push_back(1e3 * dcd.narrow.seconds_static);
    ccd_device.push_back(1e3 * ccd.narrow.seconds_ccd_device);
    ccd_events.push_back(1e3 * ccd.narrow.seconds_ccd_events);
    static_device.push_back(1e3 * dcd.narrow.seconds_static_device);
    static_events.push_back(1e3 * dcd.narrow.seconds_static_events);
    times.vf = ccd.narrow.vf_tests;
    times.ee = ccd.narrow.ee_tests;
    times.pairs = dcd.narrow.triangle_tests;
    times.grid_tests = ccd.ccd_broad.tests;
    times.collisions = collisions;
    times.intersections = events.size() - collisions;
    times.broad_memory_bytes = ccd.ccd_broad.memory_bytes;
  }
  times.total_ms = median(total);
  times.ccd_broad_ms = median(ccd_broad);
  times.bounds_ms = median(bounds);
  times.subdivision_ms = median(subdivision);
  times.registration_ms = median(registration);
  times.pairs_ms = median(pairs);
  times.features_ms = median(features);
  times.narrow_ccd_ms = median(narrow);
  times.ccd_device_ms = median(ccd_device);
  times.ccd_events_ms = median(ccd_events);
  times.static_device_ms = median(static_device);
  times.static_events_ms = median(static_events);
  times.certify_ms = median(certify);
  times.static_broad_ms = median(static_broad);
  times.static_ms = median(static_narrow);
  times.peak_device_bytes = backend.name() == "cuda" ? DeviceMemoryTracker::instance().peak_bytes() : 0;
  return times;
}

std::string row(const std::string& scene, const StepTimes& t) {
  char line[400];
  std::snprintf(line, sizeof line,
                "%-26s %-5s %-9s %9.2f %9.2f %9.2f %9.2f %9.2f %9.2f %10zu %10zu %9zu %6zu %6zu %9.1f\n",
                scene.c_str(), t.backend.c_str(), t.broad_phase.c_str(), t.total_ms, t.ccd_broad_ms,
                t.narrow_ccd_ms, t.certify_ms, t.static_broad_ms, t.static_ms, t.vf, t.ee, t.pairs, t.collisions,
                t.intersections, t.peak_device_bytes / 1048576.0);
  return line;
}

std::string parts_row(const std::string& scene, const StepTimes& t) {
  char line[200];
  std::snprintf(line, sizeof line, "%-26s %-5s %-9s %9.2f %9.2f %9.2f %9.2f\n", scene.c_str(), t.backend.c_str(),
                t.broad_phase.c_str(), t.ccd_device_ms, t.ccd_events_ms, t.static_device_ms, t.static_events_ms);
  return line;
}

struct ClothStep {
  Scene scene;
  std::vector<Vec3> x_t0, x_t1;
};

ClothStep read_cloth_ball(const std::string& data_dir) {
  const bench::PlyMesh m92 = bench::read_binary_ply(data_dir + "/meshes/cloth_ball92.ply");
  const bench::PlyMesh m93 = bench::read_binary_ply(data_dir + "/meshes/cloth_ball93.ply");
  if (m92.vertices.size() != m93.vertices.size())
    throw std::runtime_error("cloth_ball92 and cloth_ball93 differ in vertex count");
  ClothStep step;
  step.scene = Scene({make_object("cloth_ball", static_cast<Index>(m92.vertices.size()), m92.triangles)});
  step.x_t0 = m92.vertices;
  step.x_t1 = m93.vertices;
  return step;
}

/// Loop-subdivides the cloth `levels` times; the step ends at the fraction
/// `step_fraction` of the original step, on the linear trajectories.
ClothStep refine(const ClothStep& step, int levels, double step_fraction) {
  std::vector<Triangle> triangles = step.scene.triangles();
  std::vector<std::vector<Vec3>> frames = {step.x_t0, step.x_t1};
  for (int level = 0; level < levels; ++level) bench::loop_subdivide(triangles, frames);
  ClothStep refined;
  refined.scene = Scene({make_object("cloth_ball_refined", static_cast<Index>(frames[0].size()), triangles)});
  refined.x_t0 = std::move(frames[0]);
  refined.x_t1 = std::move(frames[1]);
  if (step_fraction != 1.0) {
    for (std::size_t v = 0; v < refined.x_t1.size(); ++v)
      refined.x_t1[v] = refined.x_t0[v] + step_fraction * (refined.x_t1[v] - refined.x_t0[v]);
  }
  return refined;
}

Options parse(int argc, char** argv) {
  Options options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const std::string& name) -> std::string {
      if (arg.rfind(name + "=", 0) == 0) return arg.substr(name.size() + 1);
      if (arg == name && i + 1 < argc) return argv[++i];
      return "";
    };
    if (arg.rfind("--json", 0) == 0) {
      options.json_path = value("--json");
    } else if (arg.rfind("--benchmark_out_format", 0) == 0) {
      // accepted for the bundle's benchmark runner; the output is always JSON
    } else if (arg.rfind("--benchmark_out", 0) == 0) {
      options.json_path = value("--benchmark_out");
    } else if (arg.rfind("--runs", 0) == 0) {
      options.runs = std::max(1, std::atoi(value("--runs").c_str()));
    } else if (arg.rfind("--large-runs", 0) == 0) {
      options.large_runs = std::max(1, std::atoi(value("--large-runs").c_str()));
    } else if (arg.rfind("--large-cpu-runs", 0) == 0) {
      options.large_cpu_runs = std::max(1, std::atoi(value("--large-cpu-runs").c_str()));
    } else if (arg.rfind("--write-refined", 0) == 0) {
      options.refined_dir = value("--write-refined");
      if (options.refined_dir.empty()) throw std::runtime_error("--write-refined needs a directory");
    } else if (arg == "--memory-census") {
      options.memory_census = true;
    } else if (arg == "--no-large") {
      options.large = false;
    } else if (arg == "--no-cpu") {
      options.cpu = false;
    } else if (arg == "-h" || arg == "--help") {
      std::printf(
          "usage: snag-bench-gpu [--json FILE] [--runs N (20)] [--large-runs N (5)] [--large-cpu-runs N (1)] "
          "[--no-large] [--no-cpu] [--write-refined DIR] [--memory-census]\n"
          "environment: SNAG_SHARED_DATA_DIR (reference data), SNAG_SAMPLES_DIR (sample caches)\n");
      std::exit(0);
    } else {
      throw std::runtime_error("unknown argument '" + arg + "' (see --help)");
    }
  }
  if (const char* d = std::getenv("SNAG_SHARED_DATA_DIR"); d != nullptr && *d != '\0') options.data_dir = d;
  if (const char* d = std::getenv("SNAG_SAMPLES_DIR"); d != nullptr && *d != '\0') {
    options.samples_dir = d;
  } else if (std::filesystem::is_directory(std::filesystem::path(options.data_dir) / ".." / "samples" / "cloth_ball")) {
    options.samples_dir = (std::filesystem::path(options.data_dir) / ".." / "samples").string();  // the GPU bundle
  }
  return options;
}

// Writes cloth_ball_x4_t{0,1}.ply and cloth_ball_x16_t{0,1}.ply (Loop
// subdivision once and twice, the whole step) into dir.
int write_refined(const std::string& data_dir, const std::string& dir) {
  std::filesystem::create_directories(dir);
  const ClothStep cloth = read_cloth_ball(data_dir);
  for (int levels : {1, 2}) {
    const ClothStep refined = refine(cloth, levels, 1.0);
    const std::string stem = dir + "/cloth_ball_x" + std::to_string(1 << (2 * levels));
    bench::write_binary_ply(stem + "_t0.ply", refined.x_t0, refined.scene.triangles());
    bench::write_binary_ply(stem + "_t1.ply", refined.x_t1, refined.scene.triangles());
    std::printf("%s_t{0,1}.ply: %zu triangles\n", stem.c_str(), refined.scene.triangle_count());
  }
  return 0;
}

// Where the CCD broad phase's device memory goes on the refined cloths (one
// step each): its buffers by name, in one chunk and under a 3 GiB budget
// whose chunks take at most 1 GiB, with the chunk count and time.
int print_memory_census(const std::string& data_dir) {
  const ClothStep cloth = read_cloth_ball(data_dir);
  for (int levels : {1, 2}) {
    const ClothStep refined = refine(cloth, levels, 1.0);
    for (const std::size_t budget : {std::size_t{0}, std::size_t{3} << 30}) {
      auto broad = CudaBroadPhase::create(BroadPhaseMethod::kVirtualSubdivisionGrid);
      broad->build(refined.scene, BroadPhaseSettings{});
      broad->set_memory_budget(budget, std::size_t{1} << 30);
      std::vector<VertexFaceCandidate> vf;
      std::vector<EdgeEdgeCandidate> ee;
      for (int run = 0; run < 2; ++run) broad->detect_ccd(refined.x_t0, refined.x_t1, vf, ee);  // the second reuses the plan
      std::size_t held = 0;
      const auto census = broad->memory_census();
      for (const auto& entry : census) held += entry.second;
      std::printf("cloth_ball x%d, %zu triangles, %s: %zu chunks, %zu feature parts, %zu candidates, %.1f ms, "
                  "%.1f MiB held, tracker peak %.1f MiB\n",
                  1 << (2 * levels), refined.scene.triangle_count(),
                  budget == 0 ? "no budget" : "3 GiB budget, 1 GiB chunks", broad->last_chunks(),
                  broad->last_feature_parts(), vf.size() + ee.size(), 1e3 * broad->stats().seconds_total,
                  held / 1048576.0, broad->stats().memory_bytes / 1048576.0);
      for (const auto& [name, bytes] : census)
        if (bytes >= (std::size_t{1} << 20)) std::printf("  %10.1f MiB  %s\n", bytes / 1048576.0, name.c_str());
    }
  }
  return 0;
}

int run(int argc, char** argv) {
  const Options options = parse(argc, argv);
  if (!options.refined_dir.empty()) return write_refined(options.data_dir, options.refined_dir);
  const CudaDeviceInfo device = query_cuda_device();
  if (!device.available) {
    std::fprintf(stderr, "snag-bench-gpu: no usable CUDA device: %s\n", device.why_not.c_str());
    return 2;
  }
  if (options.memory_census) return print_memory_census(options.data_dir);
  json out;
  out["device"] = {{"name", device.name},
                   {"sm", std::to_string(device.sm_major) + "." + std::to_string(device.sm_minor)},
                   {"total_memory", device.total_memory}};
  out["runs"] = options.runs;
  BackendSettings settings;
#if SNAG_HAVE_CGAL
  const std::unique_ptr<Certifier> certifier = validate::make_exact_certifier();
  settings.certifier = certifier.get();
  out["certified"] = true;
#else
  out["certified"] = false;
#endif
  std::string table, parts;

  // 1. cloth_ball92 -> 93.
  const ClothStep cloth = read_cloth_ball(options.data_dir);
  out["cloth_ball"]["triangles"] = cloth.scene.triangle_count();
  out["cloth_ball"]["vertices"] = cloth.scene.vertex_count();
  std::vector<StepTimes> cloth_times;
  {
    auto gpu = make_cuda_backend(BroadPhaseMethod::kVirtualSubdivisionGrid);
    cloth_times.push_back(time_step(*gpu, "vss", cloth.scene, settings, cloth.x_t0, cloth.x_t1, options.warmup,
                                    options.runs));
  }
  {
    auto gpu = make_cuda_backend(BroadPhaseMethod::kLargestTriangleGrid);
    cloth_times.push_back(time_step(*gpu, "largest", cloth.scene, settings, cloth.x_t0, cloth.x_t1, options.warmup,
                                    options.runs));
  }
  if (options.cpu) {
    auto cpu = make_cpu_backend();
    cloth_times.push_back(time_step(*cpu, "vss", cloth.scene, settings, cloth.x_t0, cloth.x_t1, options.warmup,
                                    options.runs));
    out["cloth_ball"]["cpu_over_gpu"] = cloth_times.back().total_ms / cloth_times.front().total_ms;
  }
  for (const StepTimes& t : cloth_times) {
    out["cloth_ball"]["steps"].push_back(t.to_json());
    table += row("cloth_ball92->93", t);
    parts += parts_row("cloth_ball92->93", t);
  }

  // 2. The narrow phase alone, on the step's candidates.
  const NarrowPhaseBenchmark narrow =
      benchmark_narrow_phase(cloth.scene, cloth.x_t0, cloth.x_t1, settings.ccd, options.warmup, options.runs);
  out["narrow_phase"] = {{"vf_candidates", narrow.vf_candidates},
                         {"ee_candidates", narrow.ee_candidates},
                         {"triangle_pairs", narrow.triangle_pairs},
                         {"screened_then_searched", narrow.searched},
                         {"two_pass_ccd_ms", narrow.two_pass_ms},
                         {"one_pass_ccd_ms", narrow.one_pass_ms},
                         {"screen_only_ccd_ms", narrow.screen_only_ms},
                         {"screen_left_undecided", narrow.left_undecided},
                         {"static_ms", narrow.static_ms},
                         {"ccd_tests_per_second", narrow.ccd_tests_per_second},
                         {"static_tests_per_second", narrow.static_tests_per_second}};

  // 3. Scaling: two Loop levels, over the whole step and over its first quarter.
  if (options.large) {
    struct Variant {
      const char* key;
      const char* label;
      double step_fraction;
    };
    for (const Variant& variant : {Variant{"refined", "cloth_ball x16", 1.0},
                                   Variant{"refined_quarter_step", "cloth_ball x16, 1/4 step", 0.25}}) {
      const ClothStep large = refine(cloth, 2, variant.step_fraction);
      json& entry = out[variant.key];
      entry["triangles"] = large.scene.triangle_count();
      entry["vertices"] = large.scene.vertex_count();
      entry["step_fraction"] = variant.step_fraction;
      std::vector<StepTimes> large_times;
      try {
        auto gpu = make_cuda_backend(BroadPhaseMethod::kVirtualSubdivisionGrid);
        large_times.push_back(
            time_step(*gpu, "vss", large.scene, settings, large.x_t0, large.x_t1, 1, options.large_runs));
        if (options.cpu && variant.step_fraction != 1.0) {
          auto cpu = make_cpu_backend();
          large_times.push_back(
              time_step(*cpu, "vss", large.scene, settings, large.x_t0, large.x_t1, 0, options.large_cpu_runs));
          entry["cpu_over_gpu"] = large_times.back().total_ms / large_times.front().total_ms;
        }
      } catch (const CudaError& error) {
        entry["error"] = error.what();
        std::fprintf(stderr, "snag-bench-gpu: %s: %s\n", variant.label, error.what());
      }
      for (const StepTimes& t : large_times) {
        entry["steps"].push_back(t.to_json());
        table += row(variant.label, t);
        parts += parts_row(variant.label, t);
      }
    }
  }

  // 4. The sample cache end to end.
  {
    const std::string dir = options.samples_dir + "/cloth_ball/";
    io::CacheOptions cache;
    cache.inputs = {{dir + "cloth.pc2", dir + "cloth_rest.obj", ""}, {dir + "body.pc2", dir + "body_rest.obj", ""}};
    for (const std::string name : {"cuda", "cpu"}) {
      if (name == "cpu" && !options.cpu) continue;
      std::vector<double> seconds;
      std::size_t frames = 0, events = 0;
      for (int run = 0; run < 4; ++run) {
        const auto start = Clock::now();
        const auto source = io::open_cache(cache);
        auto backend = name == "cuda" ? make_cuda_backend() : make_cpu_backend();
        backend->bind(source->scene(), settings);
        const ScanResult result = scan_cache(*source, *backend, ScanSettings{});
        const double s = std::chrono::duration<double>(Clock::now() - start).count();
        if (run > 0) seconds.push_back(s);
        frames = result.frames.size();
        events = result.events.size();
      }
      const double s = median(seconds);
      out["samples"][name] = {{"frames", frames}, {"events", events}, {"seconds", s}, {"frames_per_second", frames / s}};
      char line[200];
      std::snprintf(line, sizeof line, "samples/cloth_ball scan_cache on %-4s: %zu frames, %zu events, %.3f s, %.1f frames/s\n",
                    name.c_str(), frames, events, s, frames / s);
      table += line;
    }
  }

  if (!options.json_path.empty()) {
    std::ofstream file(options.json_path);
    file << out.dump(1) << "\n";
    if (!file) throw std::runtime_error("cannot write " + options.json_path);
  }
  std::printf("snag-bench-gpu on %s: medians of %d runs (%d for the refined cloth), milliseconds per step "
              "(collisions 92->93 + intersections of 93); frames stay on the device between runs\n",
              device.name.c_str(), options.runs, options.large_runs);
  std::printf("narrow phase alone (CUDA events): CCD %zu VF + %zu EE candidates: screen+search %.3f ms "
              "(%zu searched), single pass %.3f ms, %.3g tests/s; screen alone %.3f ms (%zu left undecided); "
              "static %zu pairs %.3f ms, %.3g tests/s\n",
              narrow.vf_candidates, narrow.ee_candidates, narrow.two_pass_ms, narrow.searched, narrow.one_pass_ms,
              narrow.ccd_tests_per_second, narrow.screen_only_ms, narrow.left_undecided, narrow.triangle_pairs, narrow.static_ms, narrow.static_tests_per_second);
  std::printf("%-26s %-5s %-9s %9s %9s %9s %9s %9s %9s %10s %10s %9s %6s %6s %9s\n", "scene", "back", "broad",
              "total", "ccd_broad", "ccd_narr", "certify", "dcd_broad", "dcd_narr", "vf", "ee", "pairs", "coll",
              "inter", "peak_MiB");
  std::fputs(table.c_str(), stdout);
  std::printf("narrow phases in parts, ms: on the device (CUDA events) and the events' host part (built there\n"
              "on the CPU back end; settled and copied on CUDA)\n");
  std::printf("%-26s %-5s %-9s %9s %9s %9s %9s\n", "scene", "back", "broad", "ccd_dev", "ccd_evts", "dcd_dev",
              "dcd_evts");
  std::fputs(parts.c_str(), stdout);
  return 0;
}

}  // namespace
}  // namespace snag

int main(int argc, char** argv) {
  try {
    return snag::run(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "snag-bench-gpu: %s\n", error.what());
    return 3;
  }
}
