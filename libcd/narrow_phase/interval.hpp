// Closed intervals of doubles with outward rounding, usable from host and
// device code.
//
// Each bound is computed with one correctly rounded IEEE-754 operation (round
// to nearest) and then stepped one unit in the last place outward (next_up,
// next_down: nextafter). A correctly rounded result lies within half a unit
// of the exact value, so the stepped bound is on the safe side of it (at a
// power of two the unit below is half the unit above, and one step down is
// still a whole unit of the lower binade). The enclosure therefore holds for
// every operation, subnormal results included, without changing the rounding
// mode.
//
// The host steps the bit pattern; the device steps with one fused
// multiply-add rounded outward, which gives the same doubles (see next_up).
// The GPU's time search runs thousands of these a query, and the bit steps
// took most of its code and time.
//
// Assumes round-to-nearest, no flush-to-zero, and double evaluated as double
// (x86-64 SSE2, CUDA); a fused multiply-add is harmless because each bound is a
// separate expression followed by a step outward.
#pragma once

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"

namespace snag {

namespace interval_detail {

SNAG_HD_INLINE int64_t bits_of(double x) {
#ifdef __CUDA_ARCH__
  return __double_as_longlong(x);
#else
  int64_t bits;
  memcpy(&bits, &x, sizeof bits);
  return bits;
#endif
}

SNAG_HD_INLINE double double_of(int64_t bits) {
#ifdef __CUDA_ARCH__
  return __longlong_as_double(bits);
#else
  double x;
  memcpy(&x, &bits, sizeof x);
  return x;
#endif
}

}  // namespace interval_detail

/// The next double above x: nextafter(x, +inf) for finite x. +inf and NaN
/// are returned as they are; -0 and +0 step to the smallest positive
/// subnormal, and -inf to -DBL_MAX.
///
/// The host steps the bit pattern (a library call costs more than the
/// interval operation it rounds), written as selects, without branches. The
/// device adds 2^-1075 exactly and rounds upward, one instruction: the sum
/// lies strictly between x and the next double above it (doubles are at
/// least 2^-1074 apart), and -2^-1074 gives -2^-1075, which rounds to -0 as
/// the bit step does. Only -inf needs a case of its own.
SNAG_HD_INLINE double next_up(double x) {
#ifdef __CUDA_ARCH__
  const double up = __fma_ru(interval_detail::double_of(1), 0.5, x);
  return up < -DBL_MAX ? -DBL_MAX : up;
#else
  const int64_t bits = interval_detail::bits_of(x);
  const int64_t stepped = bits + (bits < 0 ? int64_t{-1} : int64_t{1});  // away from zero above it, towards below
  const int64_t up = x == 0 ? int64_t{1} : stepped;
  return interval_detail::double_of(x < INFINITY ? up : bits);  // +inf and NaN as they are
#endif
}
/// The next double below x (see next_up).
SNAG_HD_INLINE double next_down(double x) {
#ifdef __CUDA_ARCH__
  const double down = __fma_rd(interval_detail::double_of(1), -0.5, x);
  return down > DBL_MAX ? DBL_MAX : down;
#else
  return -next_up(-x);
#endif
}

/// The largest double not above the exact value that x approximates to
/// within half a unit in the last place.
SNAG_HD_INLINE double round_down(double x) { return next_down(x); }
/// The smallest double not below the exact value that x approximates to
/// within half a unit in the last place.
SNAG_HD_INLINE double round_up(double x) { return next_up(x); }

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

/// Of conditions "value > 0": -1 when some one is certainly false (its
/// interval is strictly negative), +1 when every one is certainly true, else 0.
SNAG_HD_INLINE int all_positive(const Interval* values, int count) {
  bool all = true;
  for (int i = 0; i < count; ++i) {
    if (certainly_negative(values[i])) return -1;
    all = all && certainly_positive(values[i]);
  }
  return all ? 1 : 0;
}

/// True when a and b have strictly opposite signs.
SNAG_HD_INLINE bool opposite_signs(Interval a, Interval b) {
  return (certainly_positive(a) && certainly_negative(b)) || (certainly_negative(a) && certainly_positive(b));
}

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
