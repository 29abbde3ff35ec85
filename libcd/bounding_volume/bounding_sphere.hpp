// Bounding spheres of small point sets (the corners of a triangle, or of a
// triangle at the start and end of a time interval, whose convex hull holds
// the swept triangle). The centre is the centre of the points' bounding box,
// the radius the largest distance to a point. Spheres decide subdivision and
// the home cell only; conservativeness rests on the DOPs, so the sphere needs
// no rounding guarantee.
#pragma once

#include <cmath>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"

namespace snag {

struct Sphere {
  Vec3 centre;
  double radius = 0;
};

SNAG_HD_INLINE Sphere sphere_of_points(const Vec3* points, int n) {
  Vec3 lo = points[0], hi = points[0];
  for (int i = 1; i < n; ++i) {
    lo = min(lo, points[i]);
    hi = max(hi, points[i]);
  }
  Sphere s;
  s.centre = 0.5 * (lo + hi);
  // Keep the centre inside the box despite rounding (it names the home cell).
  s.centre = max(lo, min(hi, s.centre));
  double r2 = 0;
  for (int i = 0; i < n; ++i) {
    const double d2 = squared_norm(points[i] - s.centre);
    r2 = d2 > r2 ? d2 : r2;
  }
  s.radius = std::sqrt(r2);
  return s;
}

}  // namespace snag
