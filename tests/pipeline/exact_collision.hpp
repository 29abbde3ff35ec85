// Deciding whether a vertex-face or edge-edge pair of a step collides, for
// the oracle tests: exactly (validate/exact_ccd.hpp, about a millisecond a
// pair), or screened by the floating-point filter first (its kNo and kYes are
// proven, vertex_face_ccd.hpp) with the exact test on what it leaves
// uncertain, a thousand times cheaper on pairs far apart.
#pragma once

#include <array>
#include <vector>

#include "libcd/narrow_phase/edge_edge_ccd.hpp"
#include "libcd/narrow_phase/vertex_face_ccd.hpp"
#include "libcd/scene/scene.hpp"
#include "validate/exact_ccd.hpp"

namespace snag::test {

enum class PairKind { kVertexFace, kEdgeEdge };

/// The 8 positions of a pair in the row order of validate/exact_ccd.hpp.
/// VF: a = vertex, b = face; EE: a, b = edges. Global ids of `scene`.
inline std::array<Vec3, 8> pair_points(const Scene& scene, const std::vector<Vec3>& x_t0,
                                       const std::vector<Vec3>& x_t1, PairKind kind, Index a, Index b) {
  if (kind == PairKind::kVertexFace) {
    const Triangle& f = scene.triangles()[b];
    return {x_t0[a], x_t0[f[0]], x_t0[f[1]], x_t0[f[2]], x_t1[a], x_t1[f[0]], x_t1[f[1]], x_t1[f[2]]};
  }
  const Edge& ea = scene.edges()[a];
  const Edge& eb = scene.edges()[b];
  return {x_t0[ea[0]], x_t0[ea[1]], x_t0[eb[0]], x_t0[eb[1]], x_t1[ea[0]], x_t1[ea[1]], x_t1[eb[0]], x_t1[eb[1]]};
}

/// The exact answer (thickness 0), the earliest time of impact isolated to
/// `toi_width` (a wide interval saves the refinement when only `collides`
/// matters).
inline validate::ExactCcdResult exact_collision(PairKind kind, const std::array<Vec3, 8>& p, double toi_width = 1e-6) {
  return kind == PairKind::kVertexFace ? validate::exact_vertex_face_ccd(p, 0, toi_width)
                                       : validate::exact_edge_edge_ccd(p, 0, toi_width);
}

/// Whether the pair collides (thickness 0): the floating-point filter's
/// proven answers, the exact test where it is uncertain.
inline bool collides_screened(PairKind kind, const std::array<Vec3, 8>& p) {
  const CcdSettings settings;
  const CcdResult filter = kind == PairKind::kVertexFace
                               ? vertex_face_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings)
                               : edge_edge_ccd(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], settings);
  if (filter.answer == CcdAnswer::kNo) return false;
  if (filter.answer == CcdAnswer::kYes) return true;
  return exact_collision(kind, p, 1.0).collides;
}

}  // namespace snag::test
