// The length of the curve where triangles cross each other, from the exact
// triangle–triangle intersection segments (no voxels): the measure of an open
// mesh through another open mesh or through itself.
#pragma once

#include <cstddef>
#include <vector>

#include "volume/triangle_mesh.hpp"

namespace snag::volume {

struct CurveLength {
  double length = 0;          ///< scene units: the summed lengths of the segments
  std::size_t segments = 0;   ///< intersecting pairs whose intersection is a segment
  std::size_t coplanar = 0;   ///< intersecting pairs that overlap in their common plane (no length counted)
};

/// Sums the intersection segments of the pairs (faces_a[i] of `a`,
/// faces_b[j] of `b`) whose boxes meet. With `same` (a and b one mesh, faces_b
/// ignored) the pairs are those within faces_a, and faces that share a vertex
/// or an edge count only where they cross beyond it, by the rules of
/// validate::exact_triangles_intersect. Whether two triangles intersect is
/// decided with exact predicates and the segment constructed with CGAL's exact
/// construction kernel; its length is rounded once. Degenerate faces are skipped.
CurveLength intersection_curve_length(const TriangleMesh& a, const std::vector<std::size_t>& faces_a,
                                      const TriangleMesh& b, const std::vector<std::size_t>& faces_b, bool same);

}  // namespace snag::volume
