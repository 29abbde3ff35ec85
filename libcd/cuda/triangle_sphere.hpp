// Bounding spheres of triangles, static and swept, for the grid's cell size
// and the subdivision test of the virtual subdivision scheme (Wong, Leach and
// Zambetta, "Virtual subdivision for GPU based collision detection of
// deformable objects using a uniform grid", eq. 5.1: cell size = 3·λ·r_avg).
//
// Static: centre at the centroid, radius the largest distance from the
// centroid to a corner. Swept over a step: the smallest sphere enclosing the
// sphere at t0 and the sphere at t1 (it holds the convex hull of the six
// corners, hence the linearly moving triangle). Spheres choose the cell size
// and which triangles to subdivide; they carry no rounding guarantee (the
// conservative culling uses DOPs).
//
// Host and device code; no std:: containers, no exceptions.
#pragma once

#include <cmath>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/vec3.hpp"

namespace snag {

struct TriangleSphere {
  Vec3 centre;
  double radius = 0;  ///< scene units, ≥ 0
};

/// Sphere centred on the centroid of corners a, b, c that holds all three.
SNAG_HD_INLINE TriangleSphere centroid_sphere(Vec3 a, Vec3 b, Vec3 c) {
  TriangleSphere s;
  s.centre = (a + b + c) / 3.0;
  const double da = squared_norm(a - s.centre);
  const double db = squared_norm(b - s.centre);
  const double dc = squared_norm(c - s.centre);
  const double d_max = da > db ? (da > dc ? da : dc) : (db > dc ? db : dc);
  s.radius = std::sqrt(d_max);
  return s;
}

/// Smallest sphere that holds spheres s0 and s1.
SNAG_HD_INLINE TriangleSphere enclosing_sphere(TriangleSphere s0, TriangleSphere s1) {
  const Vec3 d = s1.centre - s0.centre;
  const double distance = std::sqrt(squared_norm(d));
  if (distance + s1.radius <= s0.radius) return s0;
  if (distance + s0.radius <= s1.radius) return s1;
  TriangleSphere s;
  s.radius = 0.5 * (distance + s0.radius + s1.radius);
  // distance > 0 here: with distance = 0 one of the two tests above holds.
  s.centre = s0.centre + ((s.radius - s0.radius) / distance) * d;
  return s;
}

/// Sphere holding triangle a, b, c as it moves linearly from a_t0, b_t0, c_t0 to a_t1, b_t1, c_t1.
SNAG_HD_INLINE TriangleSphere swept_centroid_sphere(Vec3 a_t0, Vec3 b_t0, Vec3 c_t0, Vec3 a_t1, Vec3 b_t1,
                                                    Vec3 c_t1) {
  return enclosing_sphere(centroid_sphere(a_t0, b_t0, c_t0), centroid_sphere(a_t1, b_t1, c_t1));
}

}  // namespace snag
