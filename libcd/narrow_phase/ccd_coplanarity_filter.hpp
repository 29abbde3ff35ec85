// Early exit of the CCD kernels at thickness 0: the coplanarity cubic keeps
// one strict sign over the step, usable from host and device code.
//
// A vertex touching a triangle, or two edges touching each other, puts the
// four points involved in one plane. With every point moving linearly,
// x(t) = (1 - t) x_t0 + t x_t1, the differences X(t) = x(t) - y(t) of two
// points are linear in t too, and the coplanarity function
//   g(t) = det[P(t), B(t), C(t)] = P(t) . (B(t) x C(t))
// (vertex-face: P = p - a, B = b - a, C = c - a; edge-edge: P = eb0 - ea0,
// B = ea1 - ea0, C = eb1 - eb0) is a cubic. The determinant is linear in each
// argument, so with X(t) = (1 - t) X_0 + t X_1
//   g(t) = sum_m beta_m C(3, m) t^m (1 - t)^(3 - m), m = 0..3,
//   beta_0 = D000, beta_1 = (D100 + D010 + D001) / 3,
//   beta_2 = (D110 + D101 + D011) / 3, beta_3 = D111,
// where Dijk = det[P_i, B_j, C_k]. This is the Bernstein form of g on [0, 1]
// (R. T. Farouki, "The Bernstein polynomial basis: a centennial
// retrospective", CAGD 29(6), 2012): the weights C(3, m) t^m (1 - t)^(3 - m)
// are >= 0 and sum to 1, so g(t) is a convex combination of the beta_m. When
// every beta_m is > 0 (or every one < 0), g(t) != 0 for all t in [0, 1]: the
// four points are never coplanar, no contact is possible, and the answer kNo
// is proven. The division by 3 does not change signs and is left out.
//
// Rounding bound (u = 2^-53, gamma_n = n u / (1 - n u), Higham, "Accuracy and
// Stability of Numerical Algorithms", 2nd ed., ch. 3). Inputs are finite with
// |coordinate| <= 1e60 (checked by the kernels first), so no value below can
// overflow (|differences| <= 2e60, |products of three| <= 8e180).
//  1. Each difference component is one rounded subtraction of two inputs:
//     X^ = X (1 + d), |d| <= u.
//  2. A determinant is evaluated as P^x (B^y C^z - B^z C^y) + P^y (...) +
//     P^z (...): each of its six terms passes through 3 rounded differences,
//     2 products, 1 subtraction and at most 2 additions, so
//     |D^ - D| <= gamma_8 perm, perm = sum of the six |exact terms|.
//  3. The permanent is evaluated the same way on |X^| with every term
//     non-negative: 5 roundings each, so its computed value Q >= perm^ (1 - u)^5,
//     and perm <= perm^ / (1 - u)^3 (step 1). Hence
//     |D^ - D| <= gamma_8 Q / (1 - u)^8 < 9.0e-16 Q, and |D^| < 1.000001 Q.
//  4. beta^_1 = fl(fl(D^100 + D^010) + D^001) adds at most
//     gamma_2 (|D^100| + |D^010| + |D^001|) < 2.3e-16 (Q1 + Q2 + Q3), and the
//     computed sum S of the three permanents is >= (Q1 + Q2 + Q3)(1 - u)^2.
//     So for every coefficient |beta^_m - 3 beta_m| (or |beta^ - beta| for
//     m = 0, 3) < 1.14e-15 S.
//  5. Underflow: a product may instead err by 2^-1075 absolutely; carried
//     through the at most 2e60-sized factors after it, all such errors of one
//     coefficient stay below 1e-261.
// The test uses the bound fl(fl(2e-15 S) + 1e-250) >= (1 - u)^2 (2e-15 S +
// 1e-250), which exceeds 1.14e-15 S + 1e-261: a coefficient whose computed
// value is above it is certainly positive, below its negative certainly
// negative.
//
// Where it never fires (by construction, and checked by the tests): a contact
// at t = 0 or t = 1 makes beta_0 or beta_3 zero; points coplanar for all t, a
// zero-area triangle and parallel edges make g identically zero; a contact
// inside the step makes g vanish there, which a convex combination of
// coefficients of one strict sign cannot.
#pragma once

#include <math.h>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"

namespace snag {
namespace ccd_detail {

/// Bounds the rounding error of a Bernstein coefficient relative to its
/// computed permanent (see the file comment, steps 4 and 5).
constexpr double kBernsteinErrorFactor = 2e-15;
constexpr double kBernsteinUnderflowSlack = 1e-250;

/// |a| componentwise.
SNAG_HD_INLINE Vec3 abs3(const Vec3& a) { return {fabs(a.x), fabs(a.y), fabs(a.z)}; }

/// The cross product's permanent: the cross product of |b| and |c| with every
/// minus sign made plus.
SNAG_HD_INLINE Vec3 abs_cross(const Vec3& b, const Vec3& c) {
  return {b.y * c.z + b.z * c.y, b.z * c.x + b.x * c.z, b.x * c.y + b.y * c.x};
}

/// A Bernstein coefficient's computed value and the permanent that bounds its
/// rounding error.
struct BernsteinTerm {
  double value, permanent;
};

/// The bound of |computed - exact| of a coefficient (see the file comment).
SNAG_HD_INLINE double rounding_bound(const BernsteinTerm& term) {
  return kBernsteinErrorFactor * term.permanent + kBernsteinUnderflowSlack;
}

/// The sign of a computed Bernstein coefficient: +1 or -1 when it is certain,
/// 0 when rounding could flip it.
SNAG_HD_INLINE int certain_sign(const BernsteinTerm& term) {
  const double bound = rounding_bound(term);
  return term.value > bound ? 1 : (term.value < -bound ? -1 : 0);
}

/// The coplanarity cubic's coefficients D000, 3 beta_1, 3 beta_2 and D111
/// (see the file comment), each with its permanent. The vectors X(t) are given
/// by their values at t0 and t1: P = (p0, p1), B = (b0, b1), C = (c0, c1).
struct CoplanarityCubic {
  BernsteinTerm term[4];
};

SNAG_HD_INLINE BernsteinTerm end_term(const Vec3& p, const Vec3& b, const Vec3& c) {
  return {dot(p, cross(b, c)), dot(abs3(p), abs_cross(abs3(b), abs3(c)))};
}

/// The inner coefficients 3 beta_1 (first = 0) or 3 beta_2 (first = 1).
SNAG_HD_INLINE BernsteinTerm inner_term(const Vec3 p[2], const Vec3 b[2], const Vec3 c[2], int first) {
  const int second = 1 - first;
  // 3 beta_1 = D100 + D010 + D001 and 3 beta_2 = D011 + D101 + D110, summed
  // in that order.
  const BernsteinTerm d1 = end_term(p[second], b[first], c[first]);
  const BernsteinTerm d2 = end_term(p[first], b[second], c[first]);
  const BernsteinTerm d3 = end_term(p[first], b[first], c[second]);
  return {d1.value + d2.value + d3.value, d1.permanent + d2.permanent + d3.permanent};
}

/// The cubic of the differences P, B, C at t0 and t1.
SNAG_HD_INLINE CoplanarityCubic coplanarity_cubic(const Vec3 p[2], const Vec3 b[2], const Vec3 c[2]) {
  return {{end_term(p[0], b[0], c[0]), inner_term(p, b, c, 0), inner_term(p, b, c, 1), end_term(p[1], b[1], c[1])}};
}

}  // namespace ccd_detail

/// True when det[P(t), B(t), C(t)] provably keeps one strict sign for every t
/// in [0, 1], where each X(t) = (1 - t) (x_t0 - y_t0) + t (x_t1 - y_t1) is the
/// difference of two linearly moving points (scene units). The vectors are
/// passed as the pairs of points whose differences make them:
/// (p_from, p_to) gives P = p_to - p_from, and so on, at t0 then at t1.
/// Requires finite inputs with |coordinate| <= 1e60. Never throws.
SNAG_HD_INLINE bool coplanarity_keeps_sign(const Vec3& p_from_t0, const Vec3& p_to_t0, const Vec3& b_from_t0,
                                           const Vec3& b_to_t0, const Vec3& c_from_t0, const Vec3& c_to_t0,
                                           const Vec3& p_from_t1, const Vec3& p_to_t1, const Vec3& b_from_t1,
                                           const Vec3& b_to_t1, const Vec3& c_from_t1, const Vec3& c_to_t1) {
  using ccd_detail::certain_sign;
  using ccd_detail::end_term;
  using ccd_detail::inner_term;
  const Vec3 p[2] = {p_to_t0 - p_from_t0, p_to_t1 - p_from_t1};
  const Vec3 b[2] = {b_to_t0 - b_from_t0, b_to_t1 - b_from_t1};
  const Vec3 c[2] = {c_to_t0 - c_from_t0, c_to_t1 - c_from_t1};
  // The end coefficients first: they alone settle most pairs that touch at
  // neither end, and they are the ones that vanish at a contact at t = 0 or 1.
  const int sign_0 = certain_sign(end_term(p[0], b[0], c[0]));
  if (sign_0 == 0) return false;
  if (certain_sign(end_term(p[1], b[1], c[1])) != sign_0) return false;
  if (certain_sign(inner_term(p, b, c, 0)) != sign_0) return false;
  return certain_sign(inner_term(p, b, c, 1)) == sign_0;
}

}  // namespace snag
