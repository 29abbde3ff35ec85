// Bounding volumes of the mesh's own primitives (triangles, edges, vertices):
// static (one frame) or swept (from t0 to t1, linear motion), as 18-DOPs
// inflated by the thickness, and triangle bounding spheres.
//
// A primitive moving linearly stays inside the convex hull of its corners at
// t0 and t1, so the DOP of those corners bounds the swept primitive.
// Rounding pad: every DOP is widened by rounding_pad() of the points it is
// computed from: 32·ε·max|coordinate| (ε = 2^-52). That exceeds, by more than
// a factor of two, the error of a diagonal projection (½ ulp) and the error of
// the interpolated corners of virtual child triangles (barycentric and time
// interpolation: a few ulps of the largest coordinate), so floating-point
// DOPs contain the exact ones.
#pragma once

#include <cfloat>
#include <cmath>
#include <vector>

#include "libcd/bounding_volume/bounding_sphere.hpp"
#include "libcd/bounding_volume/dop18.hpp"
#include "libcd/core/host_device.hpp"
#include "libcd/scene/scene.hpp"

namespace snag {

/// Absolute rounding pad for a DOP of the given points: 32·ε·max|coordinate|.
SNAG_HD_INLINE double rounding_pad(const Vec3* points, int n) {
  double m = 0;
  for (int i = 0; i < n; ++i) {
    const double c = std::fabs(points[i].x) > std::fabs(points[i].y) ? std::fabs(points[i].x) : std::fabs(points[i].y);
    const double d = c > std::fabs(points[i].z) ? c : std::fabs(points[i].z);
    m = d > m ? d : m;
  }
  return 32.0 * DBL_EPSILON * m;
}

/// Swept 18-DOP of a primitive with n ≤ 3 corners: corners_t0[i] move to
/// corners_t1[i]. Inflated by the rounding pad and the thickness (≥ 0, scene units).
SNAG_HD_INLINE Dop18 swept_dop(const Vec3* corners_t0, const Vec3* corners_t1, int n, double thickness) {
  Vec3 points[6];
  for (int i = 0; i < n; ++i) {
    points[i] = corners_t0[i];
    points[n + i] = corners_t1[i];
  }
  return dop_of_points(points, 2 * n, rounding_pad(points, 2 * n), thickness);
}

/// DOPs of all primitives of a scene for one step, and triangle sphere radii.
struct PrimitiveBounds {
  std::vector<Dop18> triangles;  ///< #F, global triangle ids
  std::vector<Dop18> edges;      ///< #E, global edge ids
  std::vector<Dop18> vertices;   ///< #V, global vertex ids
  /// #F radii of the triangles' bounding spheres (swept over the step for CCD),
  /// thickness included; scene units.
  std::vector<double> triangle_radii;
  Vec3 scene_lo, scene_hi;  ///< box of all positions at t0 and t1, inflated by thickness and pad
};

/// Computes PrimitiveBounds in parallel.
/// @param x_t0, x_t1  #V global positions at the start and end of the step; for
///                    static detection pass the same array twice.
/// @param thickness   ≥ 0, scene units.
/// Asserts that both arrays hold scene.vertex_count() positions.
PrimitiveBounds compute_primitive_bounds(const Scene& scene, const std::vector<Vec3>& x_t0,
                                         const std::vector<Vec3>& x_t1, double thickness);

/// compute_primitive_bounds into `out`, whose arrays are reused: a broad
/// phase that keeps its bounds from step to step writes into memory it has
/// already touched, where arrays made anew each step can come fresh from the
/// system every time, to be faulted in page by page (on the cloth_funnel
/// cache that was a third of the CPU's broad phase).
void compute_primitive_bounds(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                              double thickness, PrimitiveBounds& out);

}  // namespace snag
