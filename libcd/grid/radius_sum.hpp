// An exactly reproducible sum of non-negative radii, so that the mean radius,
// and with it the cell size 3·λ·r_avg, is the same bit for bit on the CPU (a
// sequential loop) and on the GPU (a tree reduction in any order).
//
// Every radius is scaled by 2^shift, the shift fixed by the largest radius so
// that it scales below 2^62, and truncated to a 64-bit integer; the integers
// are added in 128 bits. Integer addition is associative, so the sum does not
// depend on the order; up to 2^66 radii fit. The truncation loses less than
// 2^-62 of the largest radius per radius: far below anything that matters for
// a cell size.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "libcd/core/host_device.hpp"

namespace snag {

/// A 128-bit unsigned integer, lo + hi·2^64.
struct FixedPointSum {
  std::uint64_t lo = 0, hi = 0;
};

SNAG_HD_INLINE FixedPointSum operator+(FixedPointSum a, FixedPointSum b) {
  FixedPointSum s;
  s.lo = a.lo + b.lo;
  s.hi = a.hi + b.hi + (s.lo < a.lo ? 1u : 0u);
  return s;
}

/// The shift for radii whose largest value is max_radius (≥ 0): max_radius·2^shift < 2^62.
SNAG_HD_INLINE int radius_sum_shift(double max_radius) {
  if (!(max_radius > 0) || !std::isfinite(max_radius)) return 0;
  int exponent = 0;
  std::frexp(max_radius, &exponent);  // max_radius < 2^exponent
  return 62 - exponent;
}

/// One radius in fixed point: trunc(r·2^shift), clamped to [0, 2^63].
SNAG_HD_INLINE FixedPointSum quantize_radius(double radius, int shift) {
  const double scaled = std::ldexp(radius, shift);
  FixedPointSum q;
  if (!(scaled >= 0)) return q;  // NaN or negative: counts as 0
  q.lo = scaled >= 9223372036854775808.0 ? (std::uint64_t(1) << 63) : static_cast<std::uint64_t>(scaled);
  return q;
}

/// The mean of `count` radii whose quantized sum is `sum`; 0 when count is 0.
inline double fixed_point_mean(FixedPointSum sum, std::size_t count, int shift) {
  if (count == 0) return 0;
  const double total = std::ldexp(static_cast<double>(sum.hi), 64) + static_cast<double>(sum.lo);
  return std::ldexp(total / static_cast<double>(count), -shift);
}

}  // namespace snag
