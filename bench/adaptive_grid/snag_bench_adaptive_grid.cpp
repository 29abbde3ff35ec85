// The adaptive grid against the uniform (VSS) grid, CPU back end, in one run:
// per scene, CCD and static broad phase (tests, triangle pairs, candidates,
// milliseconds, median of --repeat runs) and the whole step through the CPU
// back end (collisions t0→t1 and intersections at t1, milliseconds, events,
// which must be equal). Scenes: the cloth_ball step of the shared data, the
// same step Loop-refined --refine times (x4 per level), and an uneven scene
// (a dense cluster of tiny triangles beside big sparse ones).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>

#include "bench/broad_phase/binary_ply.hpp"
#include "bench/gpu/loop_subdivision.hpp"
#include "libcd/cpu/cpu_backend.hpp"

namespace {

using namespace snag;
using Clock = std::chrono::steady_clock;

struct Step {
  std::string name;
  std::vector<Triangle> triangles;
  std::vector<std::vector<Vec3>> frames;  // t0, t1
};

Step cloth_ball(int refine) {
  const std::string dir = std::string(SNAG_SHARED_DATA_DIR) + "/meshes/";
  bench::PlyMesh a = bench::read_binary_ply(dir + "cloth_ball92.ply");
  bench::PlyMesh b = bench::read_binary_ply(dir + "cloth_ball93.ply");
  Step step{refine == 0 ? "cloth_ball" : "cloth_ball x" + std::to_string(1 << (2 * refine)), a.triangles,
            {a.vertices, b.vertices}};
  for (int level = 0; level < refine; ++level) bench::loop_subdivide(step.triangles, step.frames);
  return step;
}

Step uneven(int tiny, int big) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  Step step{"uneven", {}, {{}, {}}};
  auto add = [&](Vec3 c, double size) {
    const Index base = static_cast<Index>(step.frames[0].size());
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = c + Vec3{size * (u(rng) - 0.5), size * (u(rng) - 0.5), size * (u(rng) - 0.5)};
      step.frames[0].push_back(p);
      step.frames[1].push_back(p + Vec3{0.002 * (u(rng) - 0.5), 0.002 * (u(rng) - 0.5), 0.002 * (u(rng) - 0.5)});
    }
    step.triangles.push_back({base, base + 1, base + 2});
  };
  for (int k = 0; k < tiny; ++k) add(Vec3{0.3 * u(rng), 0.3 * u(rng), 0.3 * u(rng)}, 0.01);
  for (int k = 0; k < big; ++k) add(Vec3{10 * u(rng), 10 * u(rng), 10 * u(rng)}, 2.0);
  return step;
}

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void measure(const Step& step, BroadPhaseMethod method, const BroadPhaseSettings& settings, int repeat, bool whole) {
  const Scene scene({make_object(step.name, static_cast<Index>(step.frames[0].size()), step.triangles)});
  const auto& x0 = step.frames[0];
  const auto& x1 = step.frames[1];
  auto broad = make_broad_phase(method);
  broad->build(scene, settings);
  std::vector<double> ccd_ms, static_ms;
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  std::vector<TrianglePair> pairs;
  BroadPhaseStats ccd, stat;
  for (int r = 0; r < repeat; ++r) {
    auto t = Clock::now();
    broad->detect_ccd(x0, x1, vf, ee);
    ccd_ms.push_back(ms_since(t));
    ccd = broad->stats();
    t = Clock::now();
    broad->detect_static(x1, pairs);
    static_ms.push_back(ms_since(t));
    stat = broad->stats();
  }
  const char* name = method == BroadPhaseMethod::kAdaptiveGrid ? "adaptive" : "uniform";
  std::printf("%-16s %-9s %9zu %12zu %10zu %10zu %9.1f %9zu %12zu %9.1f %6zu %5d %7.0f", step.name.c_str(), name,
              step.triangles.size(), ccd.tests, ccd.triangle_pairs, ccd.candidates, median(ccd_ms), stat.triangle_pairs,
              stat.tests, median(static_ms), ccd.cells_subdivided, ccd.deepest_level, ccd.memory_bytes / 1048576.0);
  std::printf(" %10zu %10zu %7.0f %7.0f", ccd.same_root_tests, ccd.removed_by_control_bits,
              1e3 * (ccd.seconds_bounds + ccd.seconds_subdivision), 1e3 * (ccd.seconds_registration + ccd.seconds_pairs));
  if (whole) {
    CpuBackendOptions options;
    options.broad_phase = method;
    auto backend = make_cpu_backend(options);
    BackendSettings backend_settings;
    backend_settings.threads = settings.threads;
    backend->bind(scene, backend_settings);
    std::vector<Event> collisions, intersections;
    const auto t = Clock::now();
    backend->collisions(x0, x1, collisions);
    backend->intersections(x1, intersections);
    std::printf(" %9.0f %7zu %7zu", ms_since(t), collisions.size(), intersections.size());
  }
  std::printf("\n");
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"snag-bench-adaptive-grid: the adaptive grid against the uniform grid, CPU back end"};
  int refine = 1, repeat = 3, tiny = 40000, big = 200;
  bool whole = true;
  BroadPhaseSettings settings;
  settings.threads = 2;
  app.add_option("--refine", refine, "Loop levels of the refined cloth_ball (1: x4, 2: x16)")->check(CLI::Range(0, 2));
  app.add_option("--repeat", repeat, "runs per broad phase (median)")->check(CLI::Range(1, 100));
  app.add_option("--threads", settings.threads, "worker threads");
  app.add_option("--cell-limit", settings.adaptive_cell_limit, "adaptive: registrations that make a cell crowded");
  app.add_option("--depth", settings.adaptive_max_depth, "adaptive: levels below the grid")->check(CLI::Range(0, 8));
  app.add_option("--tiny", tiny, "uneven scene: tiny triangles in the cluster");
  app.add_option("--big", big, "uneven scene: big sparse triangles");
  app.add_flag("!--no-whole-step", whole, "skip the whole step through the CPU back end");
  CLI11_PARSE(app, argc, argv);
  std::printf("threads %u, adaptive cell limit %zu, depth %d; ms: median of %d\n", settings.threads,
              settings.adaptive_cell_limit, settings.adaptive_max_depth, repeat);
  std::printf("%-16s %-9s %9s %12s %10s %10s %9s %9s %12s %9s %6s %5s %7s %10s %10s %7s %7s %9s %7s %7s\n", "scene", "grid", "triangles",
              "ccd_tests", "ccd_pairs", "candidates", "ccd_ms", "st_pairs", "st_tests", "static_ms", "split", "depth",
              "MiB", "same_root", "elsewhere", "sub_ms", "grid_ms", "step_ms", "ccd_ev", "dcd_ev");
  std::vector<Step> steps;
  steps.push_back(uneven(tiny, big));
  for (int level = 0; level <= refine; ++level) steps.push_back(cloth_ball(level));
  for (const Step& step : steps)
    for (BroadPhaseMethod method : {BroadPhaseMethod::kVirtualSubdivisionGrid, BroadPhaseMethod::kAdaptiveGrid})
      measure(step, method, settings, repeat, whole);
  return 0;
}
