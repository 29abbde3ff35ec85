#include "libcd/narrow_phase/triangle_triangle_frame.hpp"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>


namespace snag {

void compute_triangle_axes(const std::vector<Triangle>& triangles, const std::vector<Vec3>& x,
                           std::vector<TriangleAxes>& axes, PredicateCounters& counters) {
  axes.resize(triangles.size());
  tbb::combinable<PredicateCounters> local_counters;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles.size(), 1024), [&](const auto& range) {
    PredicateCounters& local = local_counters.local();
    for (std::size_t f = range.begin(); f != range.end(); ++f) {
      const Triangle& t = triangles[f];
      const Vec3 p[3] = {x[t[0]], x[t[1]], x[t[2]]};
      axes[f].projection = static_cast<std::int8_t>(triangle_detail::projection_axis(p[0], p[1], p[2], &local));
      axes[f].dominant = static_cast<std::int8_t>(dominant_normal_axis(p));
    }
  });
  local_counters.combine_each([&](const PredicateCounters& local) {
    counters.calls += local.calls;
    counters.exact += local.exact;
  });
}

}  // namespace snag
