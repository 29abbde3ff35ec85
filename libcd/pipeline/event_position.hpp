// Where an event is: a representative point for reports (floating point; the
// decision itself never depends on it). Usable from host and device code.
#pragma once

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"

namespace snag {

/// Closest point of segment (a, b) to point p.
SNAG_HD_INLINE Vec3 closest_on_segment(Vec3 p, Vec3 a, Vec3 b) {
  Vec3 d = b - a;
  double len2 = dot(d, d);
  double s = len2 > 0 ? dot(p - a, d) / len2 : 0.0;
  s = s < 0 ? 0 : (s > 1 ? 1 : s);
  return a + s * d;
}

/// Midpoint of the closest points of segments (a0, a1) and (b0, b1)
/// (Ericson, Real-Time Collision Detection, 5.1.9).
SNAG_HD_INLINE Vec3 segments_meeting_point(Vec3 a0, Vec3 a1, Vec3 b0, Vec3 b1) {
  Vec3 d1 = a1 - a0, d2 = b1 - b0, r = a0 - b0;
  double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  double s = 0, t = 0;
  if (a <= 0 && e <= 0) return 0.5 * (a0 + b0);
  if (a <= 0) {
    t = f / e;
  } else {
    double c = dot(d1, r);
    if (e <= 0) {
      s = -c / a;
    } else {
      double b = dot(d1, d2), denom = a * e - b * b;
      s = denom > 0 ? (b * f - c * e) / denom : 0.0;
      s = s < 0 ? 0 : (s > 1 ? 1 : s);
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = -c / a;
      } else if (t > 1) {
        t = 1;
        s = (b - c) / a;
      }
    }
  }
  s = s < 0 ? 0 : (s > 1 ? 1 : s);
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  return 0.5 * ((a0 + s * d1) + (b0 + t * d2));
}

/// A point where two intersecting triangles overlap: the mean of the points
/// where an edge of one crosses the other's plane inside it; the mean of the
/// six corners when no such crossing is found (coplanar overlap).
SNAG_HD_INLINE Vec3 triangles_meeting_point(const Vec3 a[3], const Vec3 b[3]) {
  Vec3 sum{0, 0, 0};
  int count = 0;
  for (int side = 0; side < 2; ++side) {
    const Vec3* p = side == 0 ? a : b;
    const Vec3* q = side == 0 ? b : a;
    Vec3 n = cross(q[1] - q[0], q[2] - q[0]);
    for (int k = 0; k < 3; ++k) {
      Vec3 e0 = p[k], e1 = p[(k + 1) % 3];
      double d0 = dot(n, e0 - q[0]), d1 = dot(n, e1 - q[0]);
      if ((d0 > 0 && d1 > 0) || (d0 < 0 && d1 < 0) || d0 == d1) continue;
      Vec3 x = e0 + (d0 / (d0 - d1)) * (e1 - e0);
      sum = sum + x;
      ++count;
    }
  }
  if (count == 0) {
    for (int k = 0; k < 3; ++k) sum = sum + a[k] + b[k];
    return sum / 6.0;
  }
  return sum / static_cast<double>(count);
}

}  // namespace snag
