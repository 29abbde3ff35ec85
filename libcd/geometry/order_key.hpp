// Doubles as unsigned integers that order as the doubles do, so that the
// largest or smallest of many doubles can be taken with 64-bit integer
// atomics, in any order, with the same result (the CUDA bounds stage's scene
// box and largest radius, libcd/cuda/primitive_bounds.cu). The key of -0 lies
// just below that of +0; NaN has no place in the order.
#pragma once

#include <cstdint>
#include <cstring>

#include "libcd/core/host_device.hpp"

namespace snag {

/// An integer that orders as `d` does among doubles: for a and b not NaN,
/// order_key(a) < order_key(b) exactly when a < b, or a is -0 and b is +0.
/// The smallest of several doubles is the one whose key's complement is the
/// largest. No key is 0.
SNAG_HD_INLINE std::uint64_t order_key(double d) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &d, sizeof bits);
  return bits >> 63 ? ~bits : bits | (std::uint64_t{1} << 63);
}

/// The double whose order_key is `key`.
SNAG_HD_INLINE double from_order_key(std::uint64_t key) {
  const std::uint64_t bits = key >> 63 ? key & ~(std::uint64_t{1} << 63) : ~key;
  double d = 0;
  std::memcpy(&d, &bits, sizeof d);
  return d;
}

}  // namespace snag
