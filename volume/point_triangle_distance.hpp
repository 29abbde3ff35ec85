// The distance from a point to a triangle.
#pragma once

#include "libcd/geometry/vec3.hpp"

namespace snag::volume {

/// The squared distance from p to the closed triangle (a, b, c), by the
/// closest-point regions of C. Ericson, "Real-Time Collision Detection"
/// (2005), section 5.1.5. Degenerate triangles give the distance to their
/// segment or point.
double squared_distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace snag::volume
