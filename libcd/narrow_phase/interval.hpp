// Closed intervals of doubles with outward rounding, usable from host and
// device code.
//
// Each bound is computed with one correctly rounded IEEE-754 operation (round
// to nearest) and then stepped one unit in the last place outward with
// nextafter. A correctly rounded result lies within half a unit of the exact
// value, so the stepped bound is on the safe side of it (at a power of two the
// unit below is half the unit above, and one step down is still a whole unit
// of the lower binade). The enclosure therefore holds for every operation,
// subnormal results included, without changing the rounding mode.
//
// Assumes round-to-nearest, no flush-to-zero, and double evaluated as double
// (x86-64 SSE2, CUDA); a fused multiply-add is harmless because each bound is a
// separate expression followed by nextafter.
#pragma once

#include <cfloat>
#include <math.h>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"

namespace snag {

/// The largest double not above the exact value that x approximates to
/// within half a unit in the last place.
SNAG_HD_INLINE double round_down(double x) { return ::nextafter(x, -DBL_MAX); }
/// The smallest double not below the exact value that x approximates to
/// within half a unit in the last place.
SNAG_HD_INLINE double round_up(double x) { return ::nextafter(x, DBL_MAX); }

/// The closed interval [lo, hi]; lo <= hi.
struct Interval {
  double lo = 0, hi = 0;
};

/// The degenerate interval [x, x].
SNAG_HD_INLINE Interval point_interval(double x) { return {x, x}; }

SNAG_HD_INLINE Interval operator+(Interval a, Interval b) {
  return {round_down(a.lo + b.lo), round_up(a.hi + b.hi)};
}
SNAG_HD_INLINE Interval operator-(Interval a, Interval b) {
  return {round_down(a.lo - b.hi), round_up(a.hi - b.lo)};
}
SNAG_HD_INLINE Interval operator*(Interval a, Interval b) {
  const double p0 = a.lo * b.lo, p1 = a.lo * b.hi, p2 = a.hi * b.lo, p3 = a.hi * b.hi;
  const double lo01 = p0 < p1 ? p0 : p1, lo23 = p2 < p3 ? p2 : p3;
  const double hi01 = p0 > p1 ? p0 : p1, hi23 = p2 > p3 ? p2 : p3;
  return {round_down(lo01 < lo23 ? lo01 : lo23), round_up(hi01 > hi23 ? hi01 : hi23)};
}
/// True when every value of the interval is strictly positive.
SNAG_HD_INLINE bool certainly_positive(Interval a) { return a.lo > 0; }
/// True when every value of the interval is strictly negative.
SNAG_HD_INLINE bool certainly_negative(Interval a) { return a.hi < 0; }

/// A 3-vector of intervals (an axis-aligned box).
struct IntervalVec3 {
  Interval x, y, z;
};

SNAG_HD_INLINE IntervalVec3 operator-(const IntervalVec3& a, const IntervalVec3& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
SNAG_HD_INLINE Interval dot(const IntervalVec3& a, const IntervalVec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
SNAG_HD_INLINE IntervalVec3 cross(const IntervalVec3& a, const IntervalVec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// Encloses x_t0 + t (x_t1 - x_t0) for every t in `time` (a vertex moving
/// linearly over the step).
SNAG_HD_INLINE Interval coordinate_over(double c_t0, double c_t1, Interval time) {
  return point_interval(c_t0) + time * (point_interval(c_t1) - point_interval(c_t0));
}
SNAG_HD_INLINE IntervalVec3 position_over(const Vec3& x_t0, const Vec3& x_t1, Interval time) {
  return {coordinate_over(x_t0.x, x_t1.x, time), coordinate_over(x_t0.y, x_t1.y, time),
          coordinate_over(x_t0.z, x_t1.z, time)};
}

}  // namespace snag
