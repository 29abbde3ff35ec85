#include "tools/bench/scene_benchmark.hpp"

#include <algorithm>
#include <chrono>
#include <memory>

#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/core/error.hpp"
#include "validate/verify_candidates.hpp"

namespace snag::bench {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

/// One step's candidates of both kinds.
struct Candidates {
  std::vector<VertexFaceCandidate> vf;
  std::vector<EdgeEdgeCandidate> ee;
  std::size_t size() const { return vf.size() + ee.size(); }
};

CcdQueryPoints query_of(const Scene& scene, const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                        VertexFaceCandidate c) {
  const Triangle& f = scene.triangles()[c.face];
  return {false, {x0[c.vertex], x0[f[0]], x0[f[1]], x0[f[2]], x1[c.vertex], x1[f[0]], x1[f[1]], x1[f[2]]}};
}

CcdQueryPoints query_of(const Scene& scene, const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                        EdgeEdgeCandidate c) {
  const Edge &a = scene.edges()[c.edge_a], &b = scene.edges()[c.edge_b];
  return {true, {x0[a[0]], x0[a[1]], x0[b[0]], x0[b[1]], x1[a[0]], x1[a[1]], x1[b[0]], x1[b[1]]}};
}

/// The candidates of `all` (sorted) for which `collides` holds, in order.
template <typename Candidate, typename Decide>
std::vector<Candidate> colliding(const std::vector<Candidate>& all, Decide collides) {
  std::vector<Candidate> out;
  for (const Candidate& c : all)
    if (collides(c)) out.push_back(c);
  return out;
}

/// Members of `truth` (sorted) missing from `found` (sorted).
template <typename Candidate>
std::size_t missing(const std::vector<Candidate>& truth, const std::vector<Candidate>& found) {
  std::size_t n = 0;
  for (const Candidate& c : truth) n += !std::binary_search(found.begin(), found.end(), c);
  return n;
}

std::vector<BroadPhaseRun> broad_phase_runs(const SceneBenchmarkSettings& settings, std::size_t triangles) {
  std::vector<BroadPhaseRun> runs;
  for (double lambda : settings.lambdas) {
    BroadPhaseRun run;
    run.method = "vss";
    run.lambda = lambda;
    char name[64];
    std::snprintf(name, sizeof name, "vss lambda=%g", lambda);
    run.name = name;
    runs.push_back(run);
  }
  BroadPhaseRun no_halving;
  no_halving.method = "vss";
  no_halving.name = "vss no time halving, depth <= 5";
  no_halving.max_time_halvings = 0;
  // Without halving, Loop subdivision alone shrinks fast-moving triangles: at
  // the default 16 levels (4^16 children each) the bundled sample ran out of
  // memory, so 5 levels (1,024 children at most).
  no_halving.max_subdivision_levels = 5;
  runs.push_back(no_halving);
  for (int depth : settings.depth_caps) {
    BroadPhaseRun capped;
    capped.method = "vss";
    capped.name = "vss depth <= " + std::to_string(depth);
    capped.max_subdivision_levels = depth;
    if (depth == 0) {
      capped.max_time_halvings = 4;
      capped.name += ", halvings <= 4";
    }
    runs.push_back(capped);
  }
  BroadPhaseRun largest;
  largest.method = "largest-triangle";
  largest.name = "largest-triangle grid";
  runs.push_back(largest);
  BroadPhaseRun box;
  box.method = "box-grid";
  box.name = "box grid (CPU)";
  runs.push_back(box);
  BroadPhaseRun brute;
  brute.method = "brute-force";
  brute.name = "brute force";
  brute.skipped = triangles > settings.brute_force_max_triangles;
  runs.push_back(brute);
  return runs;
}

std::unique_ptr<BroadPhase> make_for(const BroadPhaseRun& run) {
  if (run.method == "brute-force") return make_broad_phase(BroadPhaseMethod::kBruteForce);
  if (run.method == "largest-triangle") return make_broad_phase(BroadPhaseMethod::kLargestTriangleGrid);
  if (run.method == "box-grid") return make_broad_phase(BroadPhaseMethod::kBoxGrid);
  return make_broad_phase(BroadPhaseMethod::kVirtualSubdivisionGrid);
}

/// The broad phase of `run` on one step, accumulated into `run`.
void measure_broad_phase(const Scene& scene, const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                         unsigned threads, const Candidates& truth, BroadPhaseRun& run) {
  if (run.skipped) return;
  std::unique_ptr<BroadPhase> broad = make_for(run);
  BroadPhaseSettings settings;
  settings.lambda = run.lambda;
  settings.max_subdivision_levels = run.max_subdivision_levels;
  settings.max_time_halvings = run.max_time_halvings;
  settings.threads = threads;
  broad->build(scene, settings);
  Candidates found;
  const auto start = Clock::now();
  broad->detect_ccd(x0, x1, found.vf, found.ee);
  run.seconds += seconds_since(start);
  const BroadPhaseStats& stats = broad->stats();
  run.tests += stats.tests;
  run.candidates += found.size();
  run.cells_used = std::max(run.cells_used, stats.cells_used);
  run.levels_used = std::max(run.levels_used, stats.triangles_per_level.empty() ? std::size_t{0}
                                                                                : stats.triangles_per_level.size() - 1);
  run.time_halvings += stats.time_halvings;
  run.triangles_subdivided += stats.triangles_subdivided;
  run.memory_bytes = std::max(run.memory_bytes, stats.memory_bytes);
  run.missed += missing(truth.vf, found.vf) + missing(truth.ee, found.ee);
}

/// The heavy run of one step: complete candidates, exact for each; returns the colliding ones.
Candidates heavy_step(const Scene& scene, const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                      SceneBenchmark& out) {
  Candidates complete;
  auto start = Clock::now();
  validate::complete_ccd_candidates(scene, x0, x1, 0, complete.vf, complete.ee);
  out.heavy_broad_seconds += seconds_since(start);
  out.complete_candidates += complete.size();
  start = Clock::now();
  Candidates truth;
  truth.vf = colliding(complete.vf, [&](VertexFaceCandidate c) { return exact_collides(query_of(scene, x0, x1, c)); });
  truth.ee = colliding(complete.ee, [&](EdgeEdgeCandidate c) { return exact_collides(query_of(scene, x0, x1, c)); });
  out.heavy_narrow_seconds += seconds_since(start);
  return truth;
}

/// The adaptive run of one step: the VSS grid, then the certified method's tiers.
Candidates adaptive_step(const Scene& scene, const std::vector<Vec3>& x0, const std::vector<Vec3>& x1,
                         unsigned threads, SceneBenchmark& out, Candidates& grid) {
  std::unique_ptr<BroadPhase> broad = make_broad_phase(BroadPhaseMethod::kVirtualSubdivisionGrid);
  BroadPhaseSettings settings;
  settings.threads = threads;
  broad->build(scene, settings);
  auto start = Clock::now();
  broad->detect_ccd(x0, x1, grid.vf, grid.ee);
  out.adaptive_broad_seconds += seconds_since(start);
  out.grid_candidates += grid.size();
  out.vf_candidates += grid.vf.size();
  out.ee_candidates += grid.ee.size();
  start = Clock::now();
  auto decide = [&](const CcdQueryPoints& q) {
    const TieredAnswer answer = certified_with_tier(q);
    ++out.tiers[static_cast<int>(answer.tier)];
    return answer.collides;
  };
  Candidates found;
  found.vf = colliding(grid.vf, [&](VertexFaceCandidate c) { return decide(query_of(scene, x0, x1, c)); });
  found.ee = colliding(grid.ee, [&](EdgeEdgeCandidate c) { return decide(query_of(scene, x0, x1, c)); });
  out.adaptive_narrow_seconds += seconds_since(start);
  return found;
}

void add_counts(AllMethodCounts& sum, const AllMethodCounts& step) {
  for (int m = 0; m < kCcdMethodCount; ++m) {
    sum[m].false_negatives += step[m].false_negatives;
    sum[m].false_positives += step[m].false_positives;
    sum[m].uncertain += step[m].uncertain;
    sum[m].seconds += step[m].seconds;
  }
}

}  // namespace

SceneBenchmark benchmark_scene(const FrameSource& source, const std::string& name,
                               const SceneBenchmarkSettings& settings) {
  if (source.frame_count() < 2) throw UsageError(name + ": a scene needs at least 2 frames (one CCD step)");
  const Scene& scene = source.scene();
  SceneBenchmark out;
  out.name = name;
  out.description = source.description();
  out.vertices = scene.vertex_count();
  out.triangles = scene.triangle_count();
  out.broad_phases = broad_phase_runs(settings, scene.triangle_count());
  out.steps = std::min(settings.max_steps, source.frame_count() - 1);
  std::vector<Vec3> x0, x1;
  source.read_frame(0, x1);
  for (std::size_t step = 0; step < out.steps; ++step) {
    x0.swap(x1);
    source.read_frame(step + 1, x1);
    const Candidates truth = heavy_step(scene, x0, x1, out);
    out.positives += truth.size();
    Candidates grid;
    const Candidates found = adaptive_step(scene, x0, x1, settings.threads, out, grid);
    out.same_answers = out.same_answers && found.vf == truth.vf && found.ee == truth.ee;
    // Every method on the grid's candidates; a colliding pair the grid missed
    // is a false negative of every method (none expected: the grid is complete).
    std::vector<LabelledQuery> labelled;
    for (VertexFaceCandidate c : grid.vf)
      labelled.push_back({query_of(scene, x0, x1, c), std::binary_search(truth.vf.begin(), truth.vf.end(), c)});
    for (EdgeEdgeCandidate c : grid.ee)
      labelled.push_back({query_of(scene, x0, x1, c), std::binary_search(truth.ee.begin(), truth.ee.end(), c)});
    AllMethodCounts step_counts = count_methods(labelled, settings.repeats);
    const std::size_t grid_missed = missing(truth.vf, grid.vf) + missing(truth.ee, grid.ee);
    for (MethodCounts& counts : step_counts) counts.false_negatives += grid_missed;
    add_counts(out.methods, step_counts);
    for (BroadPhaseRun& run : out.broad_phases) measure_broad_phase(scene, x0, x1, settings.threads, truth, run);
  }
  return out;
}

}  // namespace snag::bench
