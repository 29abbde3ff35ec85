// Exact-sign orientation predicates on double coordinates.
//
// Each predicate first evaluates the determinant in floating point and accepts
// its sign when it exceeds Shewchuk's proven forward error bound (his
// "errboundA" for orient2d and orient3d); otherwise it recomputes the
// determinant exactly with expansion arithmetic (expansion.hpp). The exact
// stage is not adaptive: it expands the determinant from the input
// coordinates, as Shewchuk's orient2dexact/orient3dexact do.
//   J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast
//   Robust Geometric Predicates", Discrete & Computational Geometry 18(3),
//   305-363, 1997 (Section 4 and the bounds of his predicates.c).
//
// Input range: the signs are exact when every coordinate is 0 or has magnitude
// in [2^-250, 2^250] (see is_in_exact_range), which covers every finite
// float32 value and every double a mesh cache realistically holds. In that
// range no intermediate value of the filter or of the exact stage overflows
// or underflows, which both the error bounds and the error-free
// transformations require.
//
// Sign conventions follow Shewchuk:
//   orient2d(a, b, c) > 0 when a, b, c turn counter-clockwise;
//   orient3d(a, b, c, d) > 0 when d lies below the plane through a, b, c,
//   "below" meaning a, b, c appear counter-clockwise from above. This is the
//   negative of CGAL::orientation(a, b, c, d).
// Usable from host and device code.
#pragma once

#include <cmath>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/expansion.hpp"
#include "libcd/geometry/vec3.hpp"

// The exact stages run rarely: keep them out of line so that the filtered
// fast paths stay small where they are inlined.
#if defined(__CUDACC__)
#define SNAG_EXACT_STAGE inline __host__ __device__ __noinline__
#else
#define SNAG_EXACT_STAGE inline __attribute__((noinline, cold))
#endif

namespace snag {

/// How often the predicates ran and how often the floating-point filter could
/// not decide, so that the exact stage ran. Not thread safe: keep one per
/// thread and add them up.
struct PredicateCounters {
  unsigned long long calls = 0;  ///< orientation predicates evaluated
  unsigned long long exact = 0;  ///< of those, resolved by the exact stage
};

namespace predicate_detail {

constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1: the unit roundoff
constexpr double kOrient2dErrorBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;
constexpr double kOrient3dErrorBound = (7.0 + 56.0 * kEpsilon) * kEpsilon;

SNAG_HD_INLINE int sign_of(double x) { return (x > 0.0) - (x < 0.0); }

SNAG_HD_INLINE void count(PredicateCounters* counters, bool exact) {
  if (counters) {
    ++counters->calls;
    counters->exact += exact ? 1 : 0;
  }
}

/// Exact sign of the orient2d determinant expanded from the coordinates:
/// (ax*by - bx*ay) + (bx*cy - cx*by) + (cx*ay - ax*cy).
SNAG_EXACT_STAGE int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  double ab[4], bc[4], ca[4], ab_bc[8], det[12];
  expansion::two_products_diff(ax, by, bx, ay, ab);
  expansion::two_products_diff(bx, cy, cx, by, bc);
  expansion::two_products_diff(cx, ay, ax, cy, ca);
  const int ab_bc_len = expansion::sum(4, ab, 4, bc, ab_bc);
  const int det_len = expansion::sum(ab_bc_len, ab_bc, 4, ca, det);
  return expansion::sign(det_len, det);
}

/// Exact sign of the orient3d determinant, expanded along the z column of
/// det[[a,1],[b,1],[c,1],[d,1]] into 2x2 xy-minors of the coordinates:
/// az*M(bcd) - bz*M(acd) + cz*M(abd) - dz*M(abc), where
/// M(pqr) = pq + qr + rp and pq = px*qy - qx*py.
SNAG_EXACT_STAGE int orient3d_exact(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  double ab[4], bc[4], cd[4], da[4], ac[4], ca[4], bd[4], db[4];
  expansion::two_products_diff(a.x, b.y, b.x, a.y, ab);
  expansion::two_products_diff(b.x, c.y, c.x, b.y, bc);
  expansion::two_products_diff(c.x, d.y, d.x, c.y, cd);
  expansion::two_products_diff(d.x, a.y, a.x, d.y, da);
  expansion::two_products_diff(a.x, c.y, c.x, a.y, ac);
  expansion::two_products_diff(b.x, d.y, d.x, b.y, bd);
  for (int i = 0; i < 4; ++i) {
    ca[i] = -ac[i];
    db[i] = -bd[i];
  }
  double pair[8], minor_bcd[12], minor_acd[12], minor_abd[12], minor_abc[12];
  int pair_len = expansion::sum(4, bc, 4, cd, pair);
  const int bcd_len = expansion::sum(pair_len, pair, 4, db, minor_bcd);
  pair_len = expansion::sum(4, ac, 4, cd, pair);
  const int acd_len = expansion::sum(pair_len, pair, 4, da, minor_acd);
  pair_len = expansion::sum(4, ab, 4, bd, pair);
  const int abd_len = expansion::sum(pair_len, pair, 4, da, minor_abd);
  pair_len = expansion::sum(4, ab, 4, bc, pair);
  const int abc_len = expansion::sum(pair_len, pair, 4, ca, minor_abc);

  double term_a[24], term_b[24], term_c[24], term_d[24], half_ab[48], half_cd[48], det[96];
  const int a_len = expansion::scale(bcd_len, minor_bcd, a.z, term_a);
  const int b_len = expansion::scale(acd_len, minor_acd, -b.z, term_b);
  const int c_len = expansion::scale(abd_len, minor_abd, c.z, term_c);
  const int d_len = expansion::scale(abc_len, minor_abc, -d.z, term_d);
  const int ab_len = expansion::sum(a_len, term_a, b_len, term_b, half_ab);
  const int cd_len = expansion::sum(c_len, term_c, d_len, term_d, half_cd);
  const int det_len = expansion::sum(ab_len, half_ab, cd_len, half_cd, det);
  return expansion::sign(det_len, det);
}

}  // namespace predicate_detail

/// True when x is 0 or 2^-250 <= |x| <= 2^250: the range in which the
/// predicates below return exact signs.
SNAG_HD_INLINE bool is_in_exact_range(double x) {
  const double magnitude = fabs(x);
  return x == 0.0 || (magnitude >= 0x1p-250 && magnitude <= 0x1p250);
}
SNAG_HD_INLINE bool is_in_exact_range(Vec3 p) {
  return is_in_exact_range(p.x) && is_in_exact_range(p.y) && is_in_exact_range(p.z);
}

/// Exact sign (-1, 0, +1) of det[[ax-cx, ay-cy], [bx-cx, by-cy]]: +1 when the
/// 2D points a, b, c turn counter-clockwise, 0 when collinear.
/// Coordinates must satisfy is_in_exact_range. `counters` may be null.
SNAG_HD_INLINE int orient2d(double ax, double ay, double bx, double by, double cx, double cy,
                            PredicateCounters* counters = nullptr) {
  const double left = (ax - cx) * (by - cy);
  const double right = (ay - cy) * (bx - cx);
  const double det = left - right;
  const double permanent = fabs(left) + fabs(right);
  const double bound = predicate_detail::kOrient2dErrorBound * permanent;
  // A zero permanent means every product has an exactly zero factor (no
  // underflow in range), so the determinant is exactly zero.
  if (det > bound || -det > bound || permanent == 0.0) {
    predicate_detail::count(counters, false);
    return predicate_detail::sign_of(det);
  }
  predicate_detail::count(counters, true);
  return predicate_detail::orient2d_exact(ax, ay, bx, by, cx, cy);
}

/// orient2d of the projections of 3D points onto a coordinate plane: the plane
/// that drops axis `dropped_axis` (0, 1 or 2), keeping the two following axes
/// in cyclic order ((y, z), (z, x) or (x, y)).
SNAG_HD_INLINE int orient2d_projected(Vec3 a, Vec3 b, Vec3 c, int dropped_axis,
                                      PredicateCounters* counters = nullptr) {
  const int u = dropped_axis == 2 ? 0 : dropped_axis + 1;
  const int v = u == 2 ? 0 : u + 1;
  return orient2d(a[u], a[v], b[u], b[v], c[u], c[v], counters);
}

/// Exact sign (-1, 0, +1) of det[a-d, b-d, c-d] (rows): +1 when d lies below
/// the plane through a, b, c (a, b, c counter-clockwise seen from above), 0
/// when the four points are coplanar. Equals -CGAL::orientation(a, b, c, d).
/// Coordinates must satisfy is_in_exact_range. `counters` may be null.
SNAG_HD_INLINE int orient3d(Vec3 a, Vec3 b, Vec3 c, Vec3 d, PredicateCounters* counters = nullptr) {
  const double adx = a.x - d.x, ady = a.y - d.y, adz = a.z - d.z;
  const double bdx = b.x - d.x, bdy = b.y - d.y, bdz = b.z - d.z;
  const double cdx = c.x - d.x, cdy = c.y - d.y, cdz = c.z - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (fabs(bdxcdy) + fabs(cdxbdy)) * fabs(adz) +
                           (fabs(cdxady) + fabs(adxcdy)) * fabs(bdz) +
                           (fabs(adxbdy) + fabs(bdxady)) * fabs(cdz);
  const double bound = predicate_detail::kOrient3dErrorBound * permanent;
  if (det > bound || -det > bound || permanent == 0.0) {
    predicate_detail::count(counters, false);
    return predicate_detail::sign_of(det);
  }
  predicate_detail::count(counters, true);
  return predicate_detail::orient3d_exact(a, b, c, d);
}

}  // namespace snag
