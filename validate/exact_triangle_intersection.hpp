// Exact static triangle–triangle intersection with the shared-feature rules
// of CGAL::Polygon_mesh_processing::self_intersections.
#pragma once

#include <array>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag::validate {

/// True when the three corners are collinear (or coincide), decided exactly.
/// CGAL's self_intersections reports such a face as intersecting itself and
/// pairs it with no other face.
bool exact_triangle_is_degenerate(const std::array<Vec3, 3>& corners);

/// Whether two triangles of one frame intersect, decided with exact
/// predicates, counting pairs that share a vertex or an edge only where they
/// overlap beyond the shared feature, by the rules of
/// CGAL::Polygon_mesh_processing::self_intersections:
/// - two shared vertex ids (a shared edge u–v, the third corners w of a and x
///   of b): true only when the four corners are coplanar and x lies strictly
///   on w's side of the line u–v;
/// - one shared vertex id: true when the edge of a opposite the shared vertex
///   meets triangle b, or the edge of b opposite it meets triangle a;
/// - none: true when the closed triangles share a point.
/// a, b: the corners (positions, any unit); a_ids, b_ids: their vertex ids
///   (ids are compared, not positions, to find shared features).
/// Precondition (assert): neither triangle is degenerate (see
/// exact_triangle_is_degenerate) and the ids of one triangle are distinct.
bool exact_triangles_intersect(const std::array<Vec3, 3>& a, const std::array<Index, 3>& a_ids,
                               const std::array<Vec3, 3>& b, const std::array<Index, 3>& b_ids);

}  // namespace snag::validate
