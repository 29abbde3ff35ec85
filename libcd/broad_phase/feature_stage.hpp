// The last broad-phase stage, shared by every CCD broad phase: feature pairs
// (VF, EE) of the triangle pairs through representative triangles and feature
// culling, with its counts and time recorded in the stats.
#pragma once

#include <vector>

#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/culling/representative_triangles.hpp"

namespace snag {

/// Fills vf and ee from `triangle_pairs` (see representative_feature_pairs)
/// of the step x_t0 -> x_t1, the pairs kept apart over it left out first
/// where settings.separate_triangles (at settings.thickness), and sets
/// stats' separated_triangle_pairs, vf/ee culling counts, candidates and
/// seconds_features.
void feature_stage(const Scene& scene, const RepresentativeTriangles& reps, const PrimitiveBounds& bounds,
                   const std::vector<TrianglePair>& triangle_pairs, const std::vector<Vec3>& x_t0,
                   const std::vector<Vec3>& x_t1, const BroadPhaseSettings& settings,
                   std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee, BroadPhaseStats& stats);

}  // namespace snag
