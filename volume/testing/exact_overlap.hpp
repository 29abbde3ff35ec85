// The exact oracle for overlap volumes: CGAL's corefinement of two closed
// meshes with the exact construction kernel, then the volume of the result.
#pragma once

#include "volume/triangle_mesh.hpp"

namespace snag::volume::testing {

/// The volume of the intersection of the closed meshes `a` and `b`, by
/// CGAL::Polygon_mesh_processing::corefine_and_compute_intersection and
/// volume() on Exact_predicates_exact_constructions_kernel meshes, rounded
/// once. Throws std::runtime_error when CGAL cannot (a mesh not closed or
/// self-intersecting).
double exact_overlap_volume(const TriangleMesh& a, const TriangleMesh& b);

}  // namespace snag::volume::testing
