// The GPU narrow phase alone, timed with CUDA events, for snag-bench-gpu.
#pragma once

#include <cstddef>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"
#include "libcd/scene/scene.hpp"

namespace snag {

struct NarrowPhaseBenchmark {
  std::size_t vf_candidates = 0, ee_candidates = 0, triangle_pairs = 0;
  std::size_t searched = 0;   ///< candidates left for the search pass after the screen
  double two_pass_ms = 0;     ///< median, VF + EE, screen then search (kernels, compaction, downloads)
  double one_pass_ms = 0;     ///< median, VF + EE, single pass
  double screen_only_ms = 0;  ///< median, VF + EE, the screen alone (the CUDA back end's GPU part)
  std::size_t left_undecided = 0;  ///< candidates the screen alone leaves to the caller
  double static_ms = 0;       ///< median, triangle pairs
  double ccd_tests_per_second = 0, static_tests_per_second = 0;  ///< of the two-pass CCD and the static test
};

/// Finds the candidates of the step x_t0 -> x_t1 (and the triangle pairs of
/// x_t1) with the CPU virtual subdivision grid, uploads them, and times the
/// GPU narrow phase on them: medians of `runs` runs after `warmup`.
/// Throws CudaError.
NarrowPhaseBenchmark benchmark_narrow_phase(const Scene& scene, const std::vector<Vec3>& x_t0,
                                            const std::vector<Vec3>& x_t1, const CcdSettings& settings, int warmup,
                                            int runs);

}  // namespace snag
