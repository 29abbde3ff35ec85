// Representative triangles: each vertex and each edge is assigned to exactly
// one incident triangle, so that a triangle pair yields each vertex-face and
// edge-edge pair once, and over all triangle pairs each feature pair comes
// from one triangle pair only.
//
// Curtis, Tamstorf, Manocha, "Fast collision detection for deformable models
// using representative-triangles", I3D 2008.
//
// Rule (deterministic): a vertex or edge belongs to its incident triangle of
// smallest global id. For a triangle pair (A, B) the features are
//   VF: (v, B) for v a vertex of A that A represents and that is not a corner
//       of B; and symmetrically (v, A) for the vertices B represents;
//   EE: (e, e') for e an edge A represents, e' an edge B represents, with no
//       common endpoint.
// A pair (v, f) comes only from (R(v), f), a pair (e, e') only from
// (R(e), R(e')): unique triangle pairs give unique feature pairs. Vertices in
// no triangle take part in no pair.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/broad_phase/candidates.hpp"
#include "libcd/scene/scene.hpp"

namespace snag {

struct RepresentativeTriangles {
  /// #F masks: bit i (0..2) set when the triangle represents its corner i,
  /// bit 3+i when it represents its edge i (corners i and i+1 mod 3).
  std::vector<std::uint8_t> masks;
  /// #F by 3 global edge ids of each triangle's edges (edge i = corners i, i+1).
  std::vector<std::array<Index, 3>> edge_ids;
};

/// Assigns representatives for the scene (topology only; done once).
RepresentativeTriangles assign_representative_triangles(const Scene& scene);

/// Counts of the feature stage.
struct FeatureCounts {
  std::size_t separated = 0;  ///< triangle pairs kept apart over the step (TriangleSeparation): no features
  std::size_t vf_before = 0, vf_after = 0;  ///< VF pairs produced / left after BV culling
  std::size_t ee_before = 0, ee_after = 0;  ///< EE pairs produced / left after BV culling
};

/// The step a triangle pair is tested over before its features are made:
/// a pair that triangles_separated (narrow_phase/ccd_separating_direction.hpp)
/// proves more than `thickness` apart over the whole step yields no feature
/// pairs, since each of its features lies in its triangle. The same struct
/// carries host positions to the CPU stage and device positions to the GPU's.
struct TriangleSeparation {
  const Vec3* x_t0 = nullptr;  ///< #V positions at the start and end of the step
  const Vec3* x_t1 = nullptr;
  double thickness = 0;  ///< the broad phase's (>= 0, scene units)
};

/// Feature pairs of the given (unique) triangle pairs, culled by the swept
/// DOPs of vertex against face and edge against edge; with `separation`,
/// the triangle pairs it proves apart are left out first (counts.separated)
/// and the before-culling counts are those of the pairs left. Outputs are
/// sorted and unique. Runs in parallel; the result does not depend on the
/// thread count.
void representative_feature_pairs(const Scene& scene, const RepresentativeTriangles& reps,
                                  const PrimitiveBounds& bounds, const std::vector<TrianglePair>& triangle_pairs,
                                  std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee,
                                  FeatureCounts& counts, const TriangleSeparation* separation = nullptr);

}  // namespace snag
