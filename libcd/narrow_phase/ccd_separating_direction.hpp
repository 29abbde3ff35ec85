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
// direction instead of 18 differences, and in single precision, on the
// corners' offsets from the pair's first corner: half the registers and
// twice the arithmetic rate of doubles on a GPU, and an offset's rounding
// error scales with the pair's own extent, not with where it lies in the
// scene. With ref = a_t0[0], each corner's offset z = fl64(x - ref) is
// rounded to a float and all 12 are scaled by 2^-e, the power of two that
// brings the largest |offset| into [1/2, 1) (pairs whose largest |offset|
// lies outside [2^-100, 2^120] are not tried, nor a thickness above 2^20
// times it). Writing y for the scaled floats, w = (x - ref) 2^-e for the
// exact scaled offsets and u = 2^-24 (float arithmetic, Higham's gamma_n):
//  1. |y_k - w_k| <= u + 2^-50 for each coordinate: the float's rounding
//     (u |y_k| <= u), the double's (2^-53 |w_k|), and underflow below 2^-126
//     (at most 2^-150 before the scaling, which multiplies by at most 2^99,
//     and 2^-150 where the scaling itself leaves a subnormal);
//  2. each projection p^ = fl(s . y) of a direction s of floats (any vector:
//     only the signs below must be certain) lies within
//     gamma_3 |s|_1 + (u + 2^-50) |s|_1 + 3 * 2^-126 < 2.385e-7 |s|_1
//     + 3 * 2^-126 of s . w (|y_k| < 1; three products, two sums; an
//     underflowed or flushed product is off by at most 2^-126);
//  3. the extents lo = min p^, hi = max p^ of each triangle's corners at one
//     end are exact, and r^ = fl(lo_B - hi_A) = (lo_B - hi_A)(1 + delta),
//     |delta| <= u;
//  4. the bound T = fl(fl(S (D + 5e-7)) + 1e-30), S = fl(|s_x| + |s_y| +
//     |s_z|) and D the float of fl64(fl64(d 2^-e) (1 + 1e-5)), is at least
//     (1 - u)^5 |s|_1 (D + 5e-7) + (1 - u) 1e-30 less a few 2^-126, and
//     (1 - u)^6 D >= (1 + 9e-6) d 2^-e less a few 2^-150;
//  5. so r^ > T implies, for every corner a_i of A and b_j of B,
//     s . (w_bj - w_ai) >= lo_B - hi_A - 4.77e-7 |s|_1 - 6 * 2^-126
//     > T / (1 + u) - 4.77e-7 |s|_1 - 6 * 2^-126 > d 2^-e |s|_1
//     >= d 2^-e |s|_2, since (1 - u)^6 5e-7 > 4.77e-7 and (1 - u)^2 1e-30
//     exceeds every 2^-126 and 2^-150 term: the exact offsets, and so the
//     corners themselves (scaled by 2^e), lie more than d apart along s.
// fl(lo_A - hi_B) > T gives the reverse order; both ends of the step must give
// the same one. The scaled offsets are below 1 and each direction's
// coordinates below 32, so nothing overflows. The bound grows with the
// pair's extent (5e-7 of it), so triangles closer than that beyond the
// thickness are left to the feature pairs. With fused multiply-adds (fewer
// roundings) or flushed subnormals (covered by the 2^-126 terms) the bounds
// hold too; both back ends compile this without either, so that they decide
// every pair alike.
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
/// The projection form's range, margin and slack (see "Two whole triangles"):
/// the largest |offset| tried, its inverse the smallest, the largest
/// thickness tried relative to it, the thickness's factor, and the float
/// terms of the bound T.
constexpr double kOffsetLimit = 0x1p120;
constexpr float kOffsetFloor = 0x1p-100f;
constexpr double kScaledThicknessLimit = 0x1p20;
constexpr double kCornersMarginFactor = 1 + 1e-5;
constexpr float kCornersErrorTerm = 5e-7f;
constexpr float kCornersSlack = 1e-30f;

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

/// A corner's scaled offset from the pair's first corner, in floats (see
/// "Two whole triangles").
struct CornerOffset {
  float x, y, z;
};

SNAG_HD_INLINE CornerOffset operator-(const CornerOffset& a, const CornerOffset& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
SNAG_HD_INLINE CornerOffset cross(const CornerOffset& a, const CornerOffset& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
SNAG_HD_INLINE float dot(const CornerOffset& a, const CornerOffset& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
SNAG_HD_INLINE bool operator==(const CornerOffset& a, const CornerOffset& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

/// The smaller and the larger of two finite floats. On the host a compare
/// and select, not libm's fminf and fmaxf (calls, for their NaN rule): the
/// values here are never NaN, and where they are equal zeros of two signs
/// either one serves, since only differences with them are compared.
SNAG_HD_INLINE float smaller(float a, float b) {
#if defined(__CUDA_ARCH__)
  return fminf(a, b);
#else
  return b < a ? b : a;
#endif
}
SNAG_HD_INLINE float larger(float a, float b) {
#if defined(__CUDA_ARCH__)
  return fmaxf(a, b);
#else
  return b > a ? b : a;
#endif
}

/// The extent [lo, hi] of the computed projections fl(s . x[i]) of three
/// corners (see "Two whole triangles", steps 2 and 3).
SNAG_HD_INLINE void project_corners(const CornerOffset& s, const CornerOffset x[3], float& lo, float& hi) {
  const float p0 = dot(s, x[0]), p1 = dot(s, x[1]), p2 = dot(s, x[2]);
  lo = smaller(p0, smaller(p1, p2));
  hi = larger(p0, larger(p1, p2));
}

/// +1 when the extent of B lies above that of A by more than `bound`, -1
/// when below, else 0 (step 5).
SNAG_HD_INLINE int extents_order(float lo_a, float hi_a, float lo_b, float hi_b, float bound) {
  return lo_b - hi_a > bound ? 1 : (lo_a - hi_b > bound ? -1 : 0);
}

/// The corners of triangles A and B lie strictly more than d apart along s,
/// in the same order at t0 and at t1, in projection form; `margin` is
/// fl(D + 5e-7) for the scaled thickness D (see "Two whole triangles").
SNAG_HD_INLINE bool corners_apart(const CornerOffset& s, const CornerOffset a_t0[3], const CornerOffset a_t1[3],
                                  const CornerOffset b_t0[3], const CornerOffset b_t1[3], float margin) {
  const float bound = (fabsf(s.x) + fabsf(s.y) + fabsf(s.z)) * margin + kCornersSlack;
  float lo_a, hi_a, lo_b, hi_b;
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

/// triangles_separated (below) with the corners read one at a time:
/// corner(c, i) is corner i of a_t0, a_t1, b_t0, b_t1 for c = 0 to 3 (on a
/// GPU, a read of device memory that is rounded to floats at once, so that
/// the 12 corners are never held in doubles together).
template <class Corner>
SNAG_HD_INLINE bool triangles_separated_by(const Corner& corner, double thickness) {
  using ccd_detail::CornerOffset;
  using ccd_detail::kMaxMagnitude;
  using ccd_detail::kOffsetLimit;
  if (!(thickness >= 0 && thickness <= kMaxMagnitude)) return false;
  const Vec3 ref = corner(0, 0);
  CornerOffset offset[4][3];  // a_t0, a_t1, b_t0, b_t1
  float largest = 0;
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
  for (int c = 0; c < 4; ++c) {
#if defined(__CUDA_ARCH__)
#pragma unroll
#endif
    for (int i = 0; i < 3; ++i) {
      const Vec3 x = corner(c, i);
      if (!(fabs(x.x) <= kMaxMagnitude && fabs(x.y) <= kMaxMagnitude && fabs(x.z) <= kMaxMagnitude)) return false;
      const Vec3 z = x - ref;
      if (!(fabs(z.x) <= kOffsetLimit && fabs(z.y) <= kOffsetLimit && fabs(z.z) <= kOffsetLimit)) return false;
      const CornerOffset y{static_cast<float>(z.x), static_cast<float>(z.y), static_cast<float>(z.z)};
      offset[c][i] = y;
      largest = ccd_detail::larger(largest, ccd_detail::larger(fabsf(y.x), ccd_detail::larger(fabsf(y.y), fabsf(y.z))));
    }
  }
  if (!(largest >= ccd_detail::kOffsetFloor)) return false;
  int e = 0;
  (void)frexpf(largest, &e);  // largest = m 2^e, m in [1/2, 1), e in [-99, 121]
  const double scaled_thickness = thickness * ldexp(1.0, -e);
  if (!(scaled_thickness <= ccd_detail::kScaledThicknessLimit)) return false;
  const float margin =
      static_cast<float>(scaled_thickness * ccd_detail::kCornersMarginFactor) + ccd_detail::kCornersErrorTerm;
  const float to_unit = ldexpf(1.0f, -e);
  for (int c = 0; c < 4; ++c) {
    for (int i = 0; i < 3; ++i) {
      offset[c][i].x *= to_unit;
      offset[c][i].y *= to_unit;
      offset[c][i].z *= to_unit;
    }
  }
  const CornerOffset* const ya_t0 = offset[0];
  const CornerOffset* const ya_t1 = offset[1];
  const CornerOffset* const yb_t0 = offset[2];
  const CornerOffset* const yb_t1 = offset[3];
  // A corner the two triangles share (a vertex of both, in a mesh the
  // commonest reason no direction separates them) is a zero difference,
  // which no direction separates: the answer without trying them.
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (ya_t0[i] == yb_t0[j] && ya_t1[i] == yb_t1[j]) return false;
    }
  }
  const CornerOffset na = cross(ya_t0[1] - ya_t0[0], ya_t0[2] - ya_t0[0]);
  const CornerOffset nb = cross(yb_t0[1] - yb_t0[0], yb_t0[2] - yb_t0[0]);
  // Direction k: 0 and 1 the normals at t0, 2 to 4 the in-plane normals of
  // a's edges and 5 to 7 of b's, 8 and 9 the normals at t1: one loop, so
  // that the test is written (and compiled) once.
  for (int k = 0; k < 10; ++k) {
    CornerOffset s;
    if (k < 2) {
      s = k == 0 ? na : nb;
    } else if (k < 8) {
      const bool of_a = k < 5;
      const CornerOffset* corner = of_a ? ya_t0 : yb_t0;
      const int i = of_a ? k - 2 : k - 5;
      s = cross(corner[i == 2 ? 0 : i + 1] - corner[i], of_a ? na : nb);
    } else {
      const CornerOffset* corner = k == 8 ? ya_t1 : yb_t1;
      s = cross(corner[1] - corner[0], corner[2] - corner[0]);
    }
    if (ccd_detail::corners_apart(s, ya_t0, ya_t1, yb_t0, yb_t1, margin)) return true;
  }
  return false;
}

/// True when some fixed direction provably keeps triangle A (corners a_t0[i]
/// moving linearly to a_t1[i]) strictly more than `thickness` (scene units)
/// away from triangle B for every t in [0, 1] (see the file comment, "Two
/// whole triangles"); then no feature of A touches a feature of B over the
/// step. False for inputs out of range (a coordinate not finite or above
/// ccd_detail::kMaxMagnitude, a thickness outside [0, kMaxMagnitude]), for
/// pairs whose largest corner offset lies outside [2^-100, 2^120] or is
/// below 2^-20 of the thickness, for triangles that share a corner, and for
/// degenerate ones whose directions are zero. Decided in floats, alike on
/// the host and the device. Never throws.
SNAG_HD_INLINE bool triangles_separated(const Vec3 a_t0[3], const Vec3 a_t1[3], const Vec3 b_t0[3],
                                        const Vec3 b_t1[3], double thickness) {
  const Vec3* corners[4] = {a_t0, a_t1, b_t0, b_t1};
  return triangles_separated_by([&](int c, int i) { return corners[c][i]; }, thickness);
}

}  // namespace snag
