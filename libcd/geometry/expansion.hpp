// Exact floating-point expansion arithmetic: a real number held as a sum of
// doubles whose binary digits do not overlap, so sums and products of doubles
// are represented without any rounding.
//
// Implements the error-free transformations and the zero-eliminating
// expansion sum and scaling of
//   J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast
//   Robust Geometric Predicates", Discrete & Computational Geometry 18(3),
//   305-363, 1997 (Theorems 6, 7, 13, 19; Figures 8 and 10).
// Products use a fused multiply-add, which is exact for the low part.
//
// Exactness holds as long as no intermediate value overflows or underflows;
// the callers in predicates.hpp state the input range that guarantees this.
// Usable from host and device code: fixed-size caller arrays, no recursion.
#pragma once

#include <cmath>

#include "libcd/core/host_device.hpp"

namespace snag::expansion {

/// hi + lo == a + b exactly, hi = fl(a + b) (Knuth's branch-free two-sum).
SNAG_HD_INLINE void two_sum(double a, double b, double& hi, double& lo) {
  hi = a + b;
  const double b_virtual = hi - a;
  const double a_virtual = hi - b_virtual;
  lo = (a - a_virtual) + (b - b_virtual);
}

/// hi + lo == a - b exactly, hi = fl(a - b).
SNAG_HD_INLINE void two_diff(double a, double b, double& hi, double& lo) { two_sum(a, -b, hi, lo); }

/// hi + lo == a * b exactly, hi = fl(a * b); the low part comes from one fma.
SNAG_HD_INLINE void two_product(double a, double b, double& hi, double& lo) {
  hi = a * b;
  lo = fma(a, b, -hi);
}

/// Exact a*b - c*d as a 4-component expansion, smallest component first.
/// Returns the number of components written to `out` (always 4).
SNAG_HD_INLINE int two_products_diff(double a, double b, double c, double d, double out[4]) {
  double ab_hi, ab_lo, cd_hi, cd_lo;
  two_product(a, b, ab_hi, ab_lo);
  two_product(c, d, cd_hi, cd_lo);
  // (ab_hi + ab_lo) - (cd_hi + cd_lo), Shewchuk's Two_Two_Diff.
  double i, j, k, l0, l1;
  two_diff(ab_lo, cd_lo, i, out[0]);
  two_sum(ab_hi, i, j, k);
  two_diff(k, cd_hi, l0, out[1]);
  two_sum(j, l0, l1, out[2]);
  out[3] = l1;
  return 4;
}

/// h = e + f for nonoverlapping expansions e (e_len components) and f (f_len),
/// both ordered by increasing magnitude; zero components are dropped.
/// h needs room for e_len + f_len components. Returns h's length (>= 1).
/// Shewchuk's Fast-Expansion-Sum with zero elimination (his Theorem 13);
/// relies on round-to-nearest-even.
SNAG_HD_INLINE int sum(int e_len, const double* e, int f_len, const double* f, double* h) {
  int ei = 0, fi = 0, hi = 0;
  double e_now = e[0], f_now = f[0];
  double q, q_new, h_now;
  // Take the smaller in magnitude first.
  if ((f_now > e_now) == (f_now > -e_now)) {
    q = e_now;
    ++ei;
    if (ei < e_len) e_now = e[ei];
  } else {
    q = f_now;
    ++fi;
    if (fi < f_len) f_now = f[fi];
  }
  while (ei < e_len && fi < f_len) {
    if ((f_now > e_now) == (f_now > -e_now)) {
      two_sum(q, e_now, q_new, h_now);
      ++ei;
      if (ei < e_len) e_now = e[ei];
    } else {
      two_sum(q, f_now, q_new, h_now);
      ++fi;
      if (fi < f_len) f_now = f[fi];
    }
    q = q_new;
    if (h_now != 0.0) h[hi++] = h_now;
  }
  while (ei < e_len) {
    two_sum(q, e[ei], q_new, h_now);
    ++ei;
    q = q_new;
    if (h_now != 0.0) h[hi++] = h_now;
  }
  while (fi < f_len) {
    two_sum(q, f[fi], q_new, h_now);
    ++fi;
    q = q_new;
    if (h_now != 0.0) h[hi++] = h_now;
  }
  if (q != 0.0 || hi == 0) h[hi++] = q;
  return hi;
}

/// h = b * e for a nonoverlapping expansion e ordered by increasing magnitude;
/// zero components are dropped. h needs room for 2 * e_len components.
/// Returns h's length (>= 1). Shewchuk's Scale-Expansion (his Theorem 19).
SNAG_HD_INLINE int scale(int e_len, const double* e, double b, double* h) {
  int hi = 0;
  double q, h_now, product_hi, product_lo, sum_hi;
  two_product(e[0], b, q, h_now);
  if (h_now != 0.0) h[hi++] = h_now;
  for (int i = 1; i < e_len; ++i) {
    two_product(e[i], b, product_hi, product_lo);
    two_sum(q, product_lo, sum_hi, h_now);
    if (h_now != 0.0) h[hi++] = h_now;
    two_sum(product_hi, sum_hi, q, h_now);
    if (h_now != 0.0) h[hi++] = h_now;
  }
  if (q != 0.0 || hi == 0) h[hi++] = q;
  return hi;
}

/// Negates an expansion in place.
SNAG_HD_INLINE void negate(int e_len, double* e) {
  for (int i = 0; i < e_len; ++i) e[i] = -e[i];
}

/// Sign (-1, 0, +1) of an expansion: the sign of its largest component, which
/// is the last one (zero-eliminated expansions have no zero components except
/// a single 0 for the value zero).
SNAG_HD_INLINE int sign(int e_len, const double* e) {
  const double top = e[e_len - 1];
  return (top > 0.0) - (top < 0.0);
}

}  // namespace snag::expansion
