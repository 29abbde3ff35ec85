#include "libcd/broad_phase/feature_stage.hpp"

#include <chrono>

namespace snag {

void feature_stage(const Scene& scene, const RepresentativeTriangles& reps, const PrimitiveBounds& bounds,
                   const std::vector<TrianglePair>& triangle_pairs, const std::vector<Vec3>& x_t0,
                   const std::vector<Vec3>& x_t1, const BroadPhaseSettings& settings,
                   std::vector<VertexFaceCandidate>& vf, std::vector<EdgeEdgeCandidate>& ee, BroadPhaseStats& stats) {
  const auto start = std::chrono::steady_clock::now();
  FeatureCounts counts;
  const TriangleSeparation separation{x_t0.data(), x_t1.data(), settings.thickness};
  representative_feature_pairs(scene, reps, bounds, triangle_pairs, vf, ee, counts,
                               settings.separate_triangles ? &separation : nullptr);
  stats.separated_triangle_pairs = counts.separated;
  stats.vf_before_culling = counts.vf_before;
  stats.vf_after_culling = counts.vf_after;
  stats.ee_before_culling = counts.ee_before;
  stats.ee_after_culling = counts.ee_after;
  stats.candidates = vf.size() + ee.size();
  stats.seconds_features = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace snag
