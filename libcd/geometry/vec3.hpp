// A 3-vector of doubles, usable from host and device code.
//
// Positions are stored as double: float32 input is exactly representable and
// decimal text is parsed correctly rounded, so the pipeline works on the exact
// values the cache holds.
#pragma once

#include "libcd/core/host_device.hpp"

namespace snag {

struct Vec3 {
  double x = 0, y = 0, z = 0;

  SNAG_HD_INLINE double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  SNAG_HD_INLINE double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

SNAG_HD_INLINE Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
SNAG_HD_INLINE Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
SNAG_HD_INLINE Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
SNAG_HD_INLINE Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
SNAG_HD_INLINE Vec3 operator*(Vec3 a, double s) { return {s * a.x, s * a.y, s * a.z}; }
SNAG_HD_INLINE Vec3 operator/(Vec3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
SNAG_HD_INLINE bool operator==(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
SNAG_HD_INLINE bool operator!=(Vec3 a, Vec3 b) { return !(a == b); }

SNAG_HD_INLINE double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
SNAG_HD_INLINE Vec3 cross(Vec3 a, Vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
SNAG_HD_INLINE double squared_norm(Vec3 a) { return dot(a, a); }
SNAG_HD_INLINE Vec3 min(Vec3 a, Vec3 b) {
  return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z};
}
SNAG_HD_INLINE Vec3 max(Vec3 a, Vec3 b) {
  return {a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z};
}
/// Point on the segment from a (s = 0) to b (s = 1).
SNAG_HD_INLINE Vec3 lerp(Vec3 a, Vec3 b, double s) { return a + s * (b - a); }

}  // namespace snag
