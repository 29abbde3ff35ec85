// Brute-force broad phases, the oracles of the grids.
//
// BruteForceBroadPhase returns T_root: every root triangle pair whose swept
// 18-DOPs overlap (all n·(n-1)/2 pairs tested), then the same
// representative-triangle features and feature DOP culling as the grids.
// brute_force_leaf_triangle_pairs returns T_leaf for a given set of leaves.
// For the sets and the inclusions T_leaf ⊆ T_vss ⊆ T_root, see
// virtual_subdivision_grid.hpp.
#pragma once

#include <vector>

#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/culling/representative_triangles.hpp"
#include "libcd/subdivision/virtual_subdivision.hpp"

namespace snag {

class BruteForceBroadPhase : public BroadPhase {
 public:
  void build(const Scene& scene, const BroadPhaseSettings& settings) override;
  void detect_ccd(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1, std::vector<VertexFaceCandidate>& vf,
                  std::vector<EdgeEdgeCandidate>& ee) override;
  void detect_static(const std::vector<Vec3>& x, std::vector<TrianglePair>& pairs) override;
  const BroadPhaseStats& stats() const override { return stats_; }

 private:
  std::vector<TrianglePair> triangle_pairs(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1);

  const Scene* scene_ = nullptr;
  BroadPhaseSettings settings_;
  RepresentativeTriangles reps_;
  PrimitiveBounds bounds_;
  BroadPhaseStats stats_;
};

/// T_leaf: root pairs (a < b) with overlapping root DOPs and some leaves of a
/// and of b with nested time slots and overlapping leaf DOPs. Tests all
/// L·(L-1)/2 leaf pairs (for tests: keep L small).
/// @param leaves     leaves of the roots (e.g. VirtualSubdivisionGrid::leaves()).
/// @param root_dops  #F root swept DOPs (PrimitiveBounds::triangles).
std::vector<TrianglePair> brute_force_leaf_triangle_pairs(const std::vector<Leaf>& leaves,
                                                          const std::vector<Dop18>& root_dops);

}  // namespace snag
