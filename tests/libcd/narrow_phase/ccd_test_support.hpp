// Helpers shared by the CCD kernel tests: random configurations whose answer
// is known by construction.
#pragma once

#include <array>
#include <random>

#include "libcd/geometry/vec3.hpp"

namespace snag::test {

inline Vec3 random_point(std::mt19937_64& rng, double extent) {
  std::uniform_real_distribution<double> coordinate(-extent, extent);
  return {coordinate(rng), coordinate(rng), coordinate(rng)};
}

/// Position at time t of a point moving linearly from x_t0 to x_t1.
inline Vec3 at(const Vec3& x_t0, const Vec3& x_t1, double t) { return (1 - t) * x_t0 + t * x_t1; }

}  // namespace snag::test
