// Early exit of the CCD kernels: a fixed direction that separates the two
// swept features over the whole step, usable from host and device code.
//
// Separating axis argument (S. Gottschalk, M. C. Lin and D. Manocha, "OBBTree:
// A Hierarchical Structure for Rapid Interference Detection", SIGGRAPH 1996,
// for the static case). Let s be any fixed vector, feature A the convex hull
// of points x_i(t) (a vertex; an edge's two ends) and feature B the convex
// hull of points y_j(t) (a triangle's corners; an edge's ends), all moving
// linearly. Each h_ij(t) = s . (y_j(t) - x_i(t)) is linear in t, so when
// h_ij(0) > d |s| and h_ij(1) > d |s| for every i, j (d the thickness), then
// for every t in [0, 1] and every convex combinations q_A, q_B of the points,
// s . (q_B - q_A) = sum_ij lambda_i mu_j h_ij(t) > d |s|, hence
// |q_B - q_A| > d: no contact over the step. The same holds with every
// inequality reversed (s replaced by -s). Nothing requires s to be computed
// exactly: it is any vector of doubles; only the signs of the h_ij must be
// certain.
//
// Rounding bound (u = 2^-53, gamma_n = n u / (1 - n u), Higham, "Accuracy and
// Stability of Numerical Algorithms", 2nd ed., ch. 3). Inputs are finite with
// |coordinate| <= 1e60 (checked by the kernels first), so nothing overflows.
//  1. h^ = fl(s . fl(y - x)): each of the three terms passes through one
//     rounded difference, one product and at most two sums, so
//     |h^ - h| <= gamma_4 sum_k |s_k| |y_k - x_k|, and with the computed
//     A = fl(sum_k |s_k| |fl(y_k - x_k)|) >= (1 - u)^3 sum_k |s_k| |fl(y_k - x_k)|
//     and |y_k - x_k| <= |fl(y_k - x_k)| / (1 - u): |h^ - h| < 4.45e-16 A.
//     Underflow of the products adds at most 3 * 2^-1075.
//  2. The margin: |s|_2 <= |s|_1, and M = fl(fl(d fl(|s|_1)) (1 + 1e-15))
//     >= d |s|_1 (1 - u)^4 (1 + 1e-15).
//  3. The test h^ > fl(M + fl(fl(5e-16 A) + 1e-300)): the right side is at
//     least (1 - u)^3 times the exact sum of its terms, so at least
//     (1 - u)^7 (1 + 1e-15) d |s|_1 + (1 - u)^3 (5e-16 A + 1e-300)
//     > d |s|_1 + 4.45e-16 A + 3 * 2^-1075, and the test implies
//     h > d |s|_1 >= d |s|_2 (likewise h^ < -(...) implies h < -d |s|_2).
// A fused multiply-add only removes roundings, so the bounds hold with it.
//
// Code generation: a CUDA file that defines SNAG_CCD_UNROLL_SEPARATION
// before including this header gets the loops below unrolled, so that the
// points and differences stay in registers instead of local memory. The
// CUDA feature stage's screen does: on the refined cloths it was bound by
// the L2 traffic of that local memory (×4 on an H200: 2.47 ms as written,
// 1.74 unrolled). The narrow phase's early-exit kernel does not: most of its
// candidates end the loops early, and an unrolled form ran 1.4 to 1.7 times
// as long there (cloth_ball). The results are the same either way.
//
// Directions tried: for a vertex against a triangle, the three in-plane
// normals of the triangle's edges at t = 0 and at t = 1, and, for a thickness
// above 0 (where the coplanarity exit does not apply), the triangle's normal
// at both ends; for two edges, the in-plane normals of each edge in the plane
// the two edges span, at both ends, and that plane's normal for a thickness
// above 0. A degenerate feature gives zero directions, which never separate.
//
// Two whole triangles (triangles_separated): each triangle is the convex hull
// of its three corners, and every vertex, edge and face of it lies in that
// hull, so a direction that keeps the two hulls apart over the step keeps
// every feature pair of the two triangles apart: the 6 vertex-face and 9
// edge-edge pairs of a triangle pair are decided at once. The directions are
// each triangle's normal and the in-plane normals of its edges at t = 0, then
// each normal at t = 1. Most triangle pairs of a folding cloth whose swept
// DOPs overlap are kept apart by one of them: layers apart along a normal,
// neighbours in one sheet across an edge (on the refined cloth_ball ×4 they
// decide 79% of the triangle pairs, and 84% of the feature pairs the DOPs
// kept are no longer made; on cloth_ball 64% of the triangle pairs).
// Unlike the feature pairs' exits these run before any input is checked, so
// they check the range themselves: out of it, nothing is decided.
// They are decided in projection form, which costs 12 dot products a
// direction instead of 18 differences, each with its own bound: with X the
// largest |coordinate| of the 12 corners and p^ = fl(s . x) for each corner,
//  1. |p^ - s . x| <= gamma_3 sum_k |s_k| |x_k| + 3 * 2^-1075
//     <= gamma_3 |s|_1 X + 3 * 2^-1075 (three products, two sums);
//  2. the extents lo = min p^, hi = max p^ of each triangle's corners at one
//     end are exact, and r^ = fl(lo_B - hi_A) = (lo_B - hi_A)(1 + delta),
//     |delta| <= u;
//  3. the bound T = fl(fl(fl(|s|_1) fl(fl(d (1 + 2e-15)) + fl(X 1e-15)))
//     + 1e-300) is at least (1 - u)^6 |s|_1 (d (1 + 2e-15) + X 1e-15)
//     + (1 - u) 1e-300, less a few 2^-1075 where its products underflow;
//  4. so r^ > T implies, for every corner a_i of A and b_j of B,
//     s . (b_j - a_i) >= lo_B - hi_A - 2 gamma_3 |s|_1 X - 6 * 2^-1075
//     > T / (1 + u) - 2 gamma_3 |s|_1 X - 6 * 2^-1075 > d |s|_1 >= d |s|_2,
//     since (1 - u)^7 (1 + 2e-15) > 1 and (1 - u)^7 1e-15 > 2 gamma_3.
// fl(lo_A - hi_B) > T gives the reverse order; both ends of the step must give
// the same one. The bound is looser than the differences' (it grows with X,
// not with the gap), which only matters for triangles closer than about
// 1e-15 X beyond the thickness: those are left to the feature pairs.
#pragma once

#include <math.h>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/narrow_phase/ccd_inclusion.hpp"

namespace snag {
namespace ccd_detail {

/// Bounds the rounding error of h^ relative to A (see the file comment, step 1).
constexpr double kSeparationErrorFactor = 5e-16;
constexpr double kSeparationUnderflowSlack = 1e-300;
/// Makes the thickness margin an upper bound of d |s|_2 (step 2).
constexpr double kSeparationMarginFactor = 1 + 1e-15;
/// The projection form's factors of d and of X (see "Two whole triangles").
constexpr double kCornersMarginFactor = 1 + 2e-15;
constexpr double kCornersErrorFactor = 1e-15;

/// The thickness margin of direction s (see the file comment, step 2).
SNAG_HD_INLINE double separation_margin(const Vec3& s, double d) {
  return d * (fabs(s.x) + fabs(s.y) + fabs(s.z)) * kSeparationMarginFactor;
}

/// +1 when s . diff > d |s| is certain, -1 when s . diff < -d |s| is, else
/// 0; diff is a computed difference y - x, margin separation_margin(s, d)
/// (see the file comment, steps 1 and 3).
SNAG_HD_INLINE int separation_sign(const Vec3& s, const Vec3& diff, double margin) {
  const double h = dot(s, diff);
  const double a = fabs(s.x) * fabs(diff.x) + fabs(s.y) * fabs(diff.y) + fabs(s.z) * fabs(diff.z);
  const double bound = margin + (kSeparationErrorFactor * a + kSeparationUnderflowSlack);
  return h > bound ? 1 : (h < -bound ? -1 : 0);
}

/// True when s . diff[i] > d |s| for all i < count, or s . diff[i] < -d |s|
/// for all: the points whose differences these are lie strictly apart along s.
/// diff[i] are the computed differences y - x (see the file comment).
SNAG_HD_INLINE bool separates(const Vec3& s, const Vec3* diff, int count, double d) {
  const double margin = separation_margin(s, d);
  int sign = 0;
#if defined(__CUDA_ARCH__) && defined(SNAG_CCD_UNROLL_SEPARATION)
#pragma unroll
#endif
  for (int i = 0; i < count; ++i) {
    const int this_sign = separation_sign(s, diff[i], margin);
    if (this_sign == 0 || (sign != 0 && this_sign != sign)) return false;
    sign = this_sign;
  }
  return true;
}

/// The extent [lo, hi] of the computed projections fl(s . x[i]) of three
/// corners (see "Two whole triangles", steps 1 and 2).
SNAG_HD_INLINE void project_corners(const Vec3& s, const Vec3 x[3], double& lo, double& hi) {
  const double p0 = dot(s, x[0]), p1 = dot(s, x[1]), p2 = dot(s, x[2]);
  lo = fmin(p0, fmin(p1, p2));
  hi = fmax(p0, fmax(p1, p2));
}

/// +1 when the extent of B lies above that of A by more than `bound`, -1
/// when below, else 0 (step 4).
SNAG_HD_INLINE int extents_order(double lo_a, double hi_a, double lo_b, double hi_b, double bound) {
  return lo_b - hi_a > bound ? 1 : (lo_a - hi_b > bound ? -1 : 0);
}

/// The corners of triangles A and B lie strictly more than d apart along s,
/// in the same order at t0 and at t1, in projection form; `scale` is the
/// largest |coordinate| of the 12 corners (see "Two whole triangles").
SNAG_HD_INLINE bool corners_apart(const Vec3& s, const Vec3 a_t0[3], const Vec3 a_t1[3], const Vec3 b_t0[3],
                                  const Vec3 b_t1[3], double d, double scale) {
  const double bound = (fabs(s.x) + fabs(s.y) + fabs(s.z)) * (d * kCornersMarginFactor + scale * kCornersErrorFactor) +
                       kSeparationUnderflowSlack;
  double lo_a, hi_a, lo_b, hi_b;
  project_corners(s, a_t0, lo_a, hi_a);
  project_corners(s, b_t0, lo_b, hi_b);
  const int order = extents_order(lo_a, hi_a, lo_b, hi_b, bound);
  if (order == 0) return false;
  project_corners(s, a_t1, lo_a, hi_a);
  project_corners(s, b_t1, lo_b, hi_b);
  return extents_order(lo_a, hi_a, lo_b, hi_b, bound) == order;
}

}  // namespace ccd_detail

/// True when some fixed direction provably keeps vertex p strictly more than
/// `thickness` (>= 0, scene units) away from triangle (a, b, c) for every t
/// in [0, 1], all points moving linearly from _t0 to _t1. Requires finite
/// inputs with |coordinate| <= 1e60. Never throws.
SNAG_HD_INLINE bool vertex_face_separated(const Vec3& p_t0, const Vec3& a_t0, const Vec3& b_t0, const Vec3& c_t0,
                                          const Vec3& p_t1, const Vec3& a_t1, const Vec3& b_t1, const Vec3& c_t1,
                                          double thickness) {
  using ccd_detail::separates;
  // Vertex minus each corner, at both ends.
  const Vec3 diff[6] = {p_t0 - a_t0, p_t0 - b_t0, p_t0 - c_t0, p_t1 - a_t1, p_t1 - b_t1, p_t1 - c_t1};
  const Vec3* corners[2][3] = {{&a_t0, &b_t0, &c_t0}, {&a_t1, &b_t1, &c_t1}};
#if defined(__CUDA_ARCH__) && defined(SNAG_CCD_UNROLL_SEPARATION)
#pragma unroll
#endif
  for (int end = 0; end < 2; ++end) {
    const Vec3& a = *corners[end][0];
    const Vec3& b = *corners[end][1];
    const Vec3& c = *corners[end][2];
    const Vec3 n = cross(b - a, c - a);
    if (separates(cross(b - a, n), diff, 6, thickness) || separates(cross(c - b, n), diff, 6, thickness) ||
        separates(cross(a - c, n), diff, 6, thickness)) {
      return true;
    }
    if (thickness > 0 && separates(n, diff, 6, thickness)) return true;
  }
  return false;
}

/// True when some fixed direction provably keeps edge (ea0, ea1) strictly
/// more than `thickness` (>= 0, scene units) away from edge (eb0, eb1) for
/// every t in [0, 1], all ends moving linearly from _t0 to _t1. Requires
/// finite inputs with |coordinate| <= 1e60. Never throws.
SNAG_HD_INLINE bool edge_edge_separated(const Vec3& ea0_t0, const Vec3& ea1_t0, const Vec3& eb0_t0,
                                        const Vec3& eb1_t0, const Vec3& ea0_t1, const Vec3& ea1_t1,
                                        const Vec3& eb0_t1, const Vec3& eb1_t1, double thickness) {
  using ccd_detail::separates;
  // Each end of b minus each end of a, at both ends of the step.
  const Vec3 diff[8] = {eb0_t0 - ea0_t0, eb0_t0 - ea1_t0, eb1_t0 - ea0_t0, eb1_t0 - ea1_t0,
                        eb0_t1 - ea0_t1, eb0_t1 - ea1_t1, eb1_t1 - ea0_t1, eb1_t1 - ea1_t1};
  const Vec3 da[2] = {ea1_t0 - ea0_t0, ea1_t1 - ea0_t1};
  const Vec3 db[2] = {eb1_t0 - eb0_t0, eb1_t1 - eb0_t1};
#if defined(__CUDA_ARCH__) && defined(SNAG_CCD_UNROLL_SEPARATION)
#pragma unroll
#endif
  for (int end = 0; end < 2; ++end) {
    const Vec3 n = cross(da[end], db[end]);
    if (separates(cross(da[end], n), diff, 8, thickness) || separates(cross(db[end], n), diff, 8, thickness)) {
      return true;
    }
    if (thickness > 0 && separates(n, diff, 8, thickness)) return true;
  }
  return false;
}

/// True when some fixed direction provably keeps triangle A (corners a_t0[i]
/// moving linearly to a_t1[i]) strictly more than `thickness` (scene units)
/// away from triangle B for every t in [0, 1] (see the file comment, "Two
/// whole triangles"); then no feature of A touches a feature of B over the
/// step. False for inputs out of range (a coordinate not finite or above
/// ccd_detail::kMaxMagnitude, a thickness outside [0, kMaxMagnitude]), for
/// triangles that share a corner, and for degenerate ones whose directions
/// are zero. Never throws.
SNAG_HD_INLINE bool triangles_separated(const Vec3 a_t0[3], const Vec3 a_t1[3], const Vec3 b_t0[3],
                                        const Vec3 b_t1[3], double thickness) {
  using ccd_detail::kMaxMagnitude;
  if (!(thickness >= 0 && thickness <= kMaxMagnitude)) return false;
  const Vec3* corners[4] = {a_t0, a_t1, b_t0, b_t1};
  double scale = 0;  // the largest |coordinate|, once all are known finite
  for (int c = 0; c < 4; ++c) {
    for (int i = 0; i < 3; ++i) {
      const Vec3 m{fabs(corners[c][i].x), fabs(corners[c][i].y), fabs(corners[c][i].z)};
      if (!(m.x <= kMaxMagnitude && m.y <= kMaxMagnitude && m.z <= kMaxMagnitude)) return false;
      scale = fmax(scale, fmax(m.x, fmax(m.y, m.z)));
    }
  }
  // A corner the two triangles share (a vertex of both, in a mesh the
  // commonest reason no direction separates them) is a zero difference,
  // which no direction separates: the answer without trying them.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (a_t0[i] == b_t0[j] && a_t1[i] == b_t1[j]) return false;
    }
  }
  const Vec3 na = cross(a_t0[1] - a_t0[0], a_t0[2] - a_t0[0]);
  const Vec3 nb = cross(b_t0[1] - b_t0[0], b_t0[2] - b_t0[0]);
  // Direction k: 0 and 1 the normals at t0, 2 to 4 the in-plane normals of
  // a's edges and 5 to 7 of b's, 8 and 9 the normals at t1: one loop, so
  // that the test is written (and compiled) once.
  for (int k = 0; k < 10; ++k) {
    Vec3 s;
    if (k < 2) {
      s = k == 0 ? na : nb;
    } else if (k < 8) {
      const bool of_a = k < 5;
      const Vec3* corner = of_a ? a_t0 : b_t0;
      const int i = of_a ? k - 2 : k - 5;
      s = cross(corner[i == 2 ? 0 : i + 1] - corner[i], of_a ? na : nb);
    } else {
      const Vec3* corner = k == 8 ? a_t1 : b_t1;
      s = cross(corner[1] - corner[0], corner[2] - corner[0]);
    }
    if (ccd_detail::corners_apart(s, a_t0, a_t1, b_t0, b_t1, thickness, scale)) return true;
  }
  return false;
}

}  // namespace snag
