// Helpers every CPU broad phase uses: stage timing, the worker arena's size
// and the check of the positions handed to a detection.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <string>
#include <vector>

#include "libcd/bounding_volume/dop18.hpp"
#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/core/error.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/scene.hpp"

namespace snag::broad_phase_support {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// The arena size for BroadPhaseSettings::threads (0 = all cores).
inline int arena_threads(unsigned threads) {
  return threads == 0 ? tbb::task_arena::automatic : static_cast<int>(threads);
}

/// Throws UsageError when build() was not called (scene null) or `x` (named
/// `what` in the message) does not hold one position per scene vertex.
inline void check_positions(const Scene* scene, const std::vector<Vec3>& x, const char* what) {
  if (scene == nullptr) throw UsageError("broad phase: build() must be called before detection");
  if (x.size() != scene->vertex_count())
    throw UsageError(std::string("broad phase: ") + what + " holds " + std::to_string(x.size()) +
                     " positions, the scene has " + std::to_string(scene->vertex_count()) + " vertices");
}

/// The static 18-DOP of every triangle at positions x, in parallel: the pad
/// of swept_dop over the same corners twice, so the same DOPs as
/// compute_primitive_bounds(x, x) gives.
inline void compute_static_triangle_dops(const Scene& scene, const std::vector<Vec3>& x, double thickness,
                                         std::vector<Dop18>& dops) {
  const auto& triangles = scene.triangles();
  dops.resize(triangles.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size(), 1024), [&](const auto& range) {
    for (std::size_t f = range.begin(); f != range.end(); ++f) {
      const Vec3 p[3] = {x[triangles[f][0]], x[triangles[f][1]], x[triangles[f][2]]};
      dops[f] = dop_of_points(p, 3, rounding_pad(p, 3), thickness);
    }
  });
}

}  // namespace snag::broad_phase_support
