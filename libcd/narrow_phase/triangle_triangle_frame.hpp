// The static triangle test over the pairs of one frame, on the CPU. What a
// pair test needs of each single triangle, its exact projection axis (or
// degeneracy) and its dominant normal axis, is computed once per triangle and
// frame instead of once per pair (most triangles sit in about a dozen pairs);
// each pair then runs a rejection that suits it, then, when that shows
// nothing, the exact-sign test (triangles_intersect_with_axes):
//   - triangles that share no vertex: the plane-side rejection (b's corners
//     strictly on one side of a's plane), its three signs then reused by the
//     exact-sign test;
//   - neighbours (a shared vertex or edge): the 2D exact-sign filter
//     (triangles_separated_in_projection_along).
// The answers are those of triangles_intersect.
#pragma once

#include <cstdint>
#include <vector>

#include "libcd/broad_phase/candidates.hpp"
#include "libcd/geometry/predicates.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/narrow_phase/triangle_triangle.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag {

/// A triangle's axes in one frame.
struct TriangleAxes {
  std::int8_t projection = -1;  ///< triangle_detail::projection_axis: -1 when degenerate
  std::int8_t dominant = 0;     ///< dominant_normal_axis: the 2D filter's projection
};

/// Counts of one frame's pair tests (add them up per thread).
struct StaticTestCounters {
  std::uint64_t pairs = 0;             ///< pairs tested
  std::uint64_t decided_by_plane = 0;  ///< of those, sharing no vertex, b on one side of a's plane
  std::uint64_t decided_by_filter = 0; ///< of those, shown apart by the 2D filter
  PredicateCounters axes;              ///< predicates of the per-triangle axes
  PredicateCounters plane;             ///< predicates of the plane-side rejection
  PredicateCounters filter;            ///< predicates of the 2D filter
  PredicateCounters test;              ///< predicates of the exact-sign test after it
};

/// The axes of every triangle at positions x (#V), on the calling arena's
/// threads. `axes` is resized to #F; the predicates are counted into `counters`.
void compute_triangle_axes(const std::vector<Triangle>& triangles, const std::vector<Vec3>& x,
                           std::vector<TriangleAxes>& axes, PredicateCounters& counters);

/// Prefetches what the pair tests ahead of pair i of `pairs` (sorted by a,
/// so that only b's data is scattered) will read: b's vertex ids 16 pairs
/// ahead, b's positions 8 ahead, which are far apart in a mesh whose
/// triangle order is not spatial (cloth-ball's).
inline void prefetch_pair_data(const std::vector<Triangle>& triangles, const std::vector<Vec3>& x,
                               const std::vector<TrianglePair>& pairs, std::size_t i) {
  if (i + 16 < pairs.size()) __builtin_prefetch(&triangles[pairs[i + 16].b]);
  if (i + 8 < pairs.size()) {
    const Triangle& t = triangles[pairs[i + 8].b];
    for (const Index v : t) __builtin_prefetch(&x[v]);
  }
}

/// Whether the triangles of `pair` intersect at positions x (triangles_intersect's
/// answer), given their axes (compute_triangle_axes); with `filter` set,
/// neighbours try the 2D filter first. Counts into `counters`. Does not throw.
inline bool frame_triangles_intersect(const std::vector<Triangle>& triangles, const std::vector<Vec3>& x,
                                      const std::vector<TriangleAxes>& axes, TrianglePair pair, bool filter,
                                      StaticTestCounters& counters) {
  const TriangleAxes a_axes = axes[pair.a], b_axes = axes[pair.b];
  ++counters.pairs;
  // A degenerate triangle is not tested (reported apart, as CGAL does).
  if (a_axes.projection < 0 || b_axes.projection < 0) return false;
  const Triangle& ta = triangles[pair.a];
  const Triangle& tb = triangles[pair.b];
  const Vec3 a[3] = {x[ta[0]], x[ta[1]], x[ta[2]]};
  const Vec3 b[3] = {x[tb[0]], x[tb[1]], x[tb[2]]};
  // Triangles that share no vertex are mostly layers of a fold, which the
  // plane of one leaves on one side (three signs) while their projections
  // overlap: the 2D filter would try up to 18 signs in vain, so they skip it
  // (cloth-ball, one thread: tests 0.20-0.27 -> 0.16 s, predicates 15.1M ->
  // 11.5M over 2 frames).
  const bool shares_vertex = triangle_detail::shared_ids(ta.data(), tb.data()).count != 0;
  if (!shares_vertex) {
    int side[3];
    for (int i = 0; i < 3; ++i) side[i] = orient3d(a[0], a[1], a[2], b[i], &counters.plane);
    if (side[0] * side[1] > 0 && side[1] * side[2] > 0) {
      ++counters.decided_by_plane;
      return false;
    }
    // The exact-sign test (triangles_intersect_with_axes for no shared
    // vertex) from these three signs on, instead of recomputing them (a
    // quarter of cloth-ball's pairs end here).
    return triangle_detail::closed_triangles_intersect_with_sides(a, a_axes.projection, b, b_axes.projection, side,
                                                                  &counters.test);
  }
  // Neighbours on a smooth surface are nearly coplanar: their 3D plane-side
  // signs are small, their 2D signs in the dominant projection are not.
  if (filter && triangles_separated_in_projection_along(a_axes.dominant, a, ta.data(), b, tb.data(), &counters.filter)) {
    ++counters.decided_by_filter;
    return false;
  }
  return triangles_intersect_with_axes(a, ta.data(), a_axes.projection, b, tb.data(), b_axes.projection,
                                       &counters.test);
}

}  // namespace snag
