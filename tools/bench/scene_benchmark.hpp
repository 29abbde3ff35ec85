// What a scene needed: its CCD steps run the adaptive way snag-scan runs
// them (the VSS grid, then each candidate decided by the cheapest tier of
// the certified method that can) and the heavy way (every pair of the
// complete candidate set of validate/verify_candidates.hpp, which drops only
// pairs whose swept boxes are provably apart, decided by the exact method:
// the ground truth, as snag-verify --exhaustive computes it). Also every CCD
// method on the grid's candidates against that truth, and the broad phases
// (VSS grid over a range of lambda, with and without time halving, with the
// subdivision depth capped, the largest-triangle grid, the CPU's box grid,
// brute force): tests,
// time, memory, and any colliding pair missing from their candidates.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "libcd/scene/frame_source.hpp"
#include "tools/bench/ccd_tiers.hpp"
#include "tools/bench/method_counts.hpp"

namespace snag::bench {

struct SceneBenchmarkSettings {
  std::size_t max_steps = 4;         ///< steps (frame f -> f + 1) measured, from the first
  unsigned threads = 0;              ///< broad-phase threads; 0 = all cores
  int repeats = 3;                   ///< timed passes per method (fastest kept)
  std::size_t brute_force_max_triangles = 20000;  ///< brute force (n^2 / 2 tests) skipped above this
  std::vector<double> lambdas = {1.05, 1.2, 1.5, 2, 3};  ///< the VSS grid's lambda sweep
  /// Subdivision depth caps tried (each a VSS grid at lambda 1.2). At a cap
  /// of 0 time halving alone shrinks large swept triangles; up to its default
  /// 12 halvings that cost 2e9 tests on a 404-triangle step, so a cap of 0
  /// runs with at most 4 halvings.
  std::vector<int> depth_caps = {0, 1};
};

/// One broad phase configuration on every step.
struct BroadPhaseRun {
  std::string name;                 ///< e.g. "vss lambda=1.2", "vss no time halving", "largest-triangle grid"
  std::string method;               ///< "vss", "largest-triangle", "box-grid", "brute-force"
  double lambda = 1.2;
  int max_subdivision_levels = 16, max_time_halvings = 12;
  bool skipped = false;             ///< brute force over brute_force_max_triangles
  std::size_t tests = 0;            ///< pair tests, summed over the steps
  std::size_t candidates = 0;       ///< VF + EE candidates, summed
  std::size_t cells_used = 0;       ///< largest over the steps
  std::size_t levels_used = 0;      ///< deepest subdivision level reached
  std::size_t time_halvings = 0, triangles_subdivided = 0;  ///< summed
  std::size_t memory_bytes = 0;     ///< largest over the steps (the broad phase's own estimate)
  double seconds = 0;               ///< summed
  std::size_t missed = 0;           ///< colliding pairs (ground truth) not among its candidates
};

struct SceneBenchmark {
  std::string name, description;
  std::size_t steps = 0, vertices = 0, triangles = 0;
  std::size_t positives = 0;        ///< colliding VF + EE pairs, exact, over all steps
  // The adaptive run (the VSS grid at the default lambda, the certified method's tiers).
  std::size_t grid_candidates = 0;
  std::array<std::size_t, kCcdTierCount> tiers{};  ///< candidates decided at each CcdTier
  double adaptive_broad_seconds = 0, adaptive_narrow_seconds = 0;
  // The heavy run: complete candidates, exact for every one.
  std::size_t complete_candidates = 0;
  double heavy_broad_seconds = 0, heavy_narrow_seconds = 0;
  bool same_answers = true;         ///< the adaptive run found exactly the ground truth's pairs
  AllMethodCounts methods{};        ///< every method on the grid's candidates (broad-phase misses count as FN)
  std::size_t vf_candidates = 0, ee_candidates = 0;  ///< of grid_candidates
  std::vector<BroadPhaseRun> broad_phases;
};

/// Runs the scene benchmark on the first steps of `source`.
/// Throws what the source throws while reading frames (InputError), and
/// UsageError when the source has fewer than 2 frames.
SceneBenchmark benchmark_scene(const FrameSource& source, const std::string& name,
                               const SceneBenchmarkSettings& settings);

}  // namespace snag::bench
