// Decisions of the CCD kernels by the structure of a query, before any
// search, usable from host and device code: contacts at t = 0, and pairs
// whose relative configuration does not change over the step.
//
// Why: on unwelded meshes (one vertex per face corner, coincident vertices
// moving together) many queries touch at t = 0 and often stay in contact:
// a vertex on a face's corner or edge, two edges sharing an end. No search
// can exclude them, the crossing certificates of the kernels never fire on
// them (nothing crosses), and the (t, u, v) search would run to its cap on
// each. Their answer follows from the positions at t = 0 alone.
//
// 1. Contact at t = 0 at thickness 0, decided exactly with the orientation
//    predicates of libcd/geometry/predicates.hpp (exact signs when every
//    coordinate is 0 or of magnitude in [2^-250, 2^250]; otherwise nothing
//    here decides and the search runs as before):
//    - p on the closed segment [a, b]: p, a, b collinear (the three
//      coordinate projections of (b - a) x (p - a), each an orient2d, are
//      zero) and every coordinate of p between those of a and b (for
//      collinear points this is p = a + s (b - a) with s in [0, 1], and
//      p = a when a = b);
//    - p on the closed triangle (a, b, c): p, a, b, c coplanar (orient3d = 0)
//      and, in a coordinate projection in which the triangle keeps a nonzero
//      area (orient2d(a, b, c) = s != 0, so the projection maps the common
//      plane one to one), the three edge orientations of p are 0 or of the
//      sign of s; when no projection keeps an area, a, b, c are collinear and
//      the triangle is the union of its three edges;
//    - closed segments [a0, a1] and [b0, b1] share a point: coplanar
//      (orient3d = 0) and either an end of one lies on the other, or they
//      cross properly: in a coordinate projection in which one of the triples
//      (a0, a1, b0), (a0, a1, b1), (b0, b1, a0), (b0, b1, a1) keeps a nonzero
//      area (so it maps the common plane one to one), b0 and b1 lie strictly
//      on opposite sides of line a and a0, a1 strictly on opposite sides of
//      line b. (Two coplanar segments sharing a point share an end-on-segment
//      point or a point interior to both; the latter, for segments not on one
//      line, is a proper crossing; segments on one line that overlap have an
//      end in the other.) When no projection keeps an area all four points
//      lie on one line and only the end tests can hold.
//    A contact at t = 0 is the earliest possible: kYes with toi [0, 0], at
//    any thickness.
// 2. Contact at t = 0 within a thickness d > 0: the closest point of the
//    other feature is approximated in floating point, its parameters (u, v)
//    rounded down to multiples of 2^-30 (u + v <= 1 for a triangle), and the
//    contact function F(0, u, v) evaluated as the (t, u, v) search evaluates
//    a box corner. Its rounding bound E_k (ccd_inclusion.hpp, steps 1 to 3)
//    holds for such parameters, so when F enlarged by E_k lies in the ball of
//    radius d (corner_within) the features are within d at t = 0: kYes with
//    toi [0, 0]. A poor approximation only fails to prove.
// 3. Unchanging relative configuration: when the four points move by the
//    same displacement (zero motion, or a translation of the whole pair),
//    every difference of two points is constant, so the pair is in contact at
//    some t exactly when it is at t = 0. The displacements are compared
//    exactly: two_diff gives x_t1 - x_t0 as fl(x_t1 - x_t0) plus the exact
//    rounding error, a pair that is unique for each real difference. At
//    thickness 0, item 1 then decides the query both ways (kNo when no
//    contact at t = 0).
// Everything else (a vertex sliding in the face's plane, collinear or
// zero-length edges moving apart, collapsed triangles...) goes to the
// searches, whose work is bounded by CcdSettings::max_iterations.
#pragma once

#include <math.h>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/expansion.hpp"
#include "libcd/geometry/predicates.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/narrow_phase/ccd_inclusion.hpp"
#include "libcd/narrow_phase/ccd_result.hpp"

namespace snag {
namespace ccd_detail {

/// True when every coordinate of the 4 points is in the range in which the
/// orientation predicates are exact (is_in_exact_range).
SNAG_HD_INLINE bool in_exact_range(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return is_in_exact_range(a) && is_in_exact_range(b) && is_in_exact_range(c) && is_in_exact_range(d);
}

SNAG_HD_INLINE bool between(double x, double a, double b) {
  return (a <= x && x <= b) || (b <= x && x <= a);
}

/// Exactly: p lies on the closed segment [a, b] (p = a when a = b).
/// Coordinates must satisfy is_in_exact_range.
SNAG_HD_INLINE bool point_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  for (int k = 0; k < 3; ++k) {
    if (!between(p[k], a[k], b[k])) return false;
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (orient2d_projected(a, b, p, axis) != 0) return false;
  }
  return true;
}

/// Exactly: p lies on the closed triangle (a, b, c), which may be collapsed
/// to a segment or a point. Coordinates must satisfy is_in_exact_range.
SNAG_HD_INLINE bool point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  if (orient3d(a, b, c, p) != 0) return false;
  for (int axis = 0; axis < 3; ++axis) {
    const int area = orient2d_projected(a, b, c, axis);
    if (area == 0) continue;
    return orient2d_projected(a, b, p, axis) * area >= 0 && orient2d_projected(b, c, p, axis) * area >= 0 &&
           orient2d_projected(c, a, p, axis) * area >= 0;
  }
  return point_on_segment(p, a, b) || point_on_segment(p, b, c) || point_on_segment(p, c, a);
}

/// Exactly: the closed segments [a0, a1] and [b0, b1] share a point (either
/// may be a single point). Coordinates must satisfy is_in_exact_range.
SNAG_HD_INLINE bool segments_meet(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  if (orient3d(a0, a1, b0, b1) != 0) return false;
  if (point_on_segment(a0, b0, b1) || point_on_segment(a1, b0, b1) || point_on_segment(b0, a0, a1) ||
      point_on_segment(b1, a0, a1)) {
    return true;
  }
  for (int axis = 0; axis < 3; ++axis) {
    const int side_b0 = orient2d_projected(a0, a1, b0, axis), side_b1 = orient2d_projected(a0, a1, b1, axis);
    const int side_a0 = orient2d_projected(b0, b1, a0, axis), side_a1 = orient2d_projected(b0, b1, a1, axis);
    if (side_b0 == 0 && side_b1 == 0 && side_a0 == 0 && side_a1 == 0) continue;
    return side_b0 * side_b1 < 0 && side_a0 * side_a1 < 0;
  }
  return false;
}

/// Exactly: x_t1 - x_t0 = y_t1 - y_t0 (see the file comment, item 3).
SNAG_HD_INLINE bool same_displacement(const Vec3& x_t0, const Vec3& x_t1, const Vec3& y_t0, const Vec3& y_t1) {
  for (int k = 0; k < 3; ++k) {
    double x_hi, x_lo, y_hi, y_lo;
    expansion::two_diff(x_t1[k], x_t0[k], x_hi, x_lo);
    expansion::two_diff(y_t1[k], y_t0[k], y_hi, y_lo);
    if (!(x_hi == y_hi && x_lo == y_lo)) return false;
  }
  return true;
}

/// Exactly: the four points (points[0..3] at t0, points[4..7] at t1) share
/// one displacement, so every difference of two of them is constant.
SNAG_HD_INLINE bool moves_together(const Vec3 points[8]) {
  for (int i = 1; i < 4; ++i) {
    if (!same_displacement(points[0], points[4], points[i], points[4 + i])) return false;
  }
  return true;
}

/// x rounded down to a multiple of 2^-30 and clamped to [0, 1]: a parameter
/// for which the corner rounding bound of ccd_inclusion.hpp holds.
SNAG_HD_INLINE double dyadic_parameter(double x) {
  constexpr double kScale = 1073741824.0;  // 2^30
  if (!(x > 0)) return 0;
  if (x >= 1) return 1;
  return floor(x * kScale) / kScale;
}

/// True when F(0, u, v) of `contact`, for the given parameters (rounded to
/// dyadic ones here), provably lies within distance d of the origin.
template <class Contact>
SNAG_HD_INLINE bool within_at_start(const Contact& contact, double u, double v, double d) {
  const double t[2] = {0, 0}, uu[2] = {u, u}, vv[2] = {v, v};
  Vec3 f[8];
  contact.corner_values(t, uu, vv, f);
  double error[3];
  corner_error_bounds(contact.points, error);
  return corner_within(f[0], error, round_down(d * d));
}

/// Barycentric parameters (u, v) (weights of b and c) of a point of the
/// closed triangle (a, b, c) near the one closest to p, in floating point
/// (C. Ericson, "Real-Time Collision Detection", 2005, section 5.1.5); only
/// an approximation, for within_at_start to check.
SNAG_HD_INLINE void closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, double* u,
                                        double* v) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  *u = 0;
  *v = 0;
  if (d1 <= 0 && d2 <= 0) return;
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) {
    *u = 1;
    return;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    *u = d1 - d3 != 0 ? d1 / (d1 - d3) : 0;
    return;
  }
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) {
    *v = 1;
    return;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    *v = d2 - d6 != 0 ? d2 / (d2 - d6) : 0;
    return;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double w = (d4 - d3) + (d5 - d6) != 0 ? (d4 - d3) / ((d4 - d3) + (d5 - d6)) : 0;
    *u = 1 - w;
    *v = w;
    return;
  }
  const double sum = va + vb + vc;
  if (sum != 0 && isfinite(sum)) {
    *u = vb / sum;
    *v = vc / sum;
  }
}

SNAG_HD_INLINE double clamp01(double x) { return x > 0 ? (x < 1 ? x : 1) : 0; }

/// Parameters (u, v) of points of the closed segments [a0, a1] and [b0, b1]
/// near the closest pair, in floating point (Ericson, section 5.1.9); only an
/// approximation, for within_at_start to check.
SNAG_HD_INLINE void closest_on_segments(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1, double* u,
                                        double* v) {
  const Vec3 da = a1 - a0, db = b1 - b0, r = a0 - b0;
  const double aa = dot(da, da), bb = dot(db, db), f = dot(db, r);
  double s = 0, t = 0;
  if (aa == 0 && bb == 0) {
  } else if (aa == 0) {
    t = clamp01(f / bb);
  } else {
    const double c = dot(da, r);
    if (bb == 0) {
      s = clamp01(-c / aa);
    } else {
      const double ab = dot(da, db), denominator = aa * bb - ab * ab;
      s = denominator > 0 ? clamp01((ab * f - c * bb) / denominator) : 0;
      t = (ab * s + f) / bb;
      if (t < 0) {
        t = 0;
        s = clamp01(-c / aa);
      } else if (t > 1) {
        t = 1;
        s = clamp01((ab - c) / aa);
      }
    }
  }
  *u = s == s ? s : 0;  // NaN from overflow: any parameter will do
  *v = t == t ? t : 0;
}

}  // namespace ccd_detail
}  // namespace snag
