// Sweep and prune: the triangles' boxes sorted along one axis, each swept
// against those that start before it ends. The CPU's other classic broad
// phase, kept beside the box grid (box_grid.hpp) so that the two can be
// measured side by side (snag-bench-pipeline's static table).
//
//   1. 18-DOPs of the triangles (static, or swept over the step); the sweep
//      axis is the one of x, y, z along which the boxes' extent is the
//      smallest share of the scene's (fewest boxes overlap along it);
//   2. the triangles sorted by their box's low end along that axis (ties by
//      id), with their boxes copied into that order;
//   3. for each triangle, in parallel over fixed blocks of the order, the
//      triangles after it whose low end is at most its high end: their
//      boxes along the other two axes, then (with detect_static_leaving_out,
//      after dropping those that share an apart vertex) their DOPs;
//   4. each pair as (min, max), the blocks concatenated and sorted.
//
// The set returned is T_root exactly, as for the box grid: two DOPs that
// overlap overlap along the sweep axis, so the one that starts later (or
// has the larger id, when they start together) starts before the other
// ends, and is met in its sweep.
//
// Baraff, "Dynamic simulation of non-penetrating rigid bodies", 1992 (sort
// and sweep); Ericson, "Real-Time Collision Detection", 2005, §7.5.
#pragma once

#include <tbb/task_arena.h>

#include <memory>
#include <utility>
#include <vector>

#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/culling/representative_triangles.hpp"

namespace snag {

class SweepAndPruneBroadPhase : public BroadPhase {
 public:
  void build(const Scene& scene, const BroadPhaseSettings& settings) override;
  void detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<VertexFaceCandidate>& vf,
                  std::vector<EdgeEdgeCandidate>& ee) override;
  void detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) override;
  /// detect_static without the pairs that share an apart vertex (dropped
  /// before their DOPs are read); find_apart runs alongside the sort.
  void detect_static_leaving_out(const std::vector<Vec3>& x, const std::vector<unsigned char>& apart,
                                 std::vector<TrianglePair>& pairs, const std::function<void()>& find_apart) override;
  using BroadPhase::detect_static_leaving_out;
  const BroadPhaseStats& stats() const override { return stats_; }

 private:
  /// Sorts the boxes of `dops` along the sweep axis (sort_boxes), and runs
  /// find_apart (if any) alongside.
  void sort_boxes(const std::vector<Dop18>& dops, const std::function<void()>& find_apart);
  /// The pairs whose DOPs overlap, sorted, into `pairs`; with `apart`, none
  /// that shares a flagged vertex. After sort_boxes.
  void sweep(const std::vector<Dop18>& dops, std::vector<TrianglePair>& pairs, const unsigned char* apart);
  void static_pairs(const std::vector<Vec3>& x, const std::vector<unsigned char>* apart,
                    const std::function<void()>& find_apart, std::vector<TrianglePair>& pairs);

  const Scene* scene_ = nullptr;
  BroadPhaseSettings settings_;
  RepresentativeTriangles reps_;
  BroadPhaseStats stats_;
  PrimitiveBounds bounds_;           ///< CCD: all primitives' swept DOPs
  std::vector<Dop18> static_dops_;   ///< static detection: the triangles' DOPs
  std::vector<TrianglePair> pairs_;  ///< CCD: the triangle pairs before the feature stage
  std::unique_ptr<tbb::task_arena> arena_;
  int axis_ = 0;  ///< the sweep axis
  /// A triangle's box in the sweep order: along the sweep axis, then the
  /// other two.
  struct SortedBox {
    double lo, hi;
    double lo1, hi1, lo2, hi2;
    Index triangle;
  };
  std::vector<std::pair<double, Index>> keys_;  ///< #F, (low end, triangle), sorted
  std::vector<SortedBox> sorted_;               ///< #F, in the sweep order
  std::vector<std::vector<TrianglePair>> block_pairs_;
  std::vector<std::size_t> block_tests_, block_culled_, block_left_out_;
};

}  // namespace snag
