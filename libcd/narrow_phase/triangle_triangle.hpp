// Static triangle-triangle intersection (DCD narrow phase) with exact signs.
//
// Two triangles of one frame intersect when their closed point sets share a
// point; triangles that share a vertex or an edge (by vertex id) count only
// where they overlap beyond the shared feature. The rules for shared features
// and degenerate triangles are those of CGAL's
// Polygon_mesh_processing::self_intersections (CGAL 5.5,
// do_faces_intersect), so the two agree pair for pair:
//   - shared edge: intersect iff the four points are coplanar and the two
//     opposite vertices lie strictly on the same side of the shared edge;
//   - shared vertex: intersect iff the edge opposite the shared vertex in one
//     triangle meets the other (closed) triangle, for either triangle;
//   - nothing shared: the closed triangles intersect;
//   - all three ids shared (a duplicated face): intersect (they coincide);
//   - a degenerate triangle (collinear vertices, repeated ids included) is
//     not tested: the result is false with adjacency `degenerate`, and the
//     caller reports degenerate faces on their own, as CGAL does with its
//     (f, f) pairs.
//
// The closed test for unrelated triangles uses the observation behind
//   P. Guigue and O. Devillers, "Fast and Robust Triangle-Triangle Overlap
//   Test Using Orientation Predicates", Journal of Graphics Tools 8(1), 2003:
// after the plane-side rejection with orient3d, two triangles meet iff an edge
// of one meets the other (an endpoint of the overlap of their intersection
// intervals, or of the coplanar overlap region, lies on an edge). Each
// segment-triangle test is decided by orient3d signs, and coplanar cases by
// orient2d in a projection that keeps the triangle non-degenerate, so every
// contact (vertex on face, edge in the other plane, coplanar overlap) is
// decided exactly.
//
// Coordinates must satisfy is_in_exact_range (predicates.hpp).
// Usable from host and device code.
#pragma once

#include <cmath>
#include <cstdint>

#include "libcd/core/host_device.hpp"
#include "libcd/geometry/predicates.hpp"
#include "libcd/geometry/vec3.hpp"

namespace snag {

/// How two triangles are related by their vertex ids (and degeneracy).
enum class TriangleAdjacency : std::uint8_t {
  none,           ///< no shared vertex id
  shared_vertex,  ///< exactly one shared vertex id
  shared_edge,    ///< exactly two shared vertex ids
  same_vertices,  ///< all three ids shared: a duplicated face
  degenerate,     ///< at least one triangle has collinear vertices; not tested
};

/// Name of an adjacency, for reports ("none", "shared_vertex", ...).
const char* to_string(TriangleAdjacency adjacency);

namespace triangle_detail {

/// How the vertex ids of triangles a and b match.
struct SharedIds {
  int count = 0;             ///< matching (i, j) pairs, a_ids[i] == b_ids[j]
  int a_last = 0, b_last = 0;  ///< the last match: with count 1, the shared vertex
  int a_opposite = 0, b_opposite = 0;  ///< with count 2, the vertex of each not shared
};

SNAG_HD_INLINE SharedIds shared_ids(const std::uint32_t a_ids[3], const std::uint32_t b_ids[3]) {
  SharedIds shared;
  bool a_is_shared[3] = {false, false, false};
  bool b_is_shared[3] = {false, false, false};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a_ids[i] == b_ids[j]) {
        ++shared.count;
        a_is_shared[i] = b_is_shared[j] = true;
        shared.a_last = i;
        shared.b_last = j;
      }
  for (int i = 0; i < 3; ++i) {
    if (!a_is_shared[i]) shared.a_opposite = i;
    if (!b_is_shared[i]) shared.b_opposite = i;
  }
  return shared;
}

/// A coordinate axis whose dropping projects the triangle to a non-degenerate
/// 2D triangle, or -1 when the triangle is degenerate (its vertices are
/// collinear: every projection is degenerate).
SNAG_HD_INLINE int projection_axis(Vec3 t0, Vec3 t1, Vec3 t2, PredicateCounters* counters) {
  const Vec3 n = cross(t1 - t0, t2 - t0);
  const double nx = fabs(n.x), ny = fabs(n.y), nz = fabs(n.z);
  // Try the floating-point dominant axis first; the exact test decides.
  const int first = (nx >= ny && nx >= nz) ? 0 : (ny >= nz ? 1 : 2);
  for (int k = 0; k < 3; ++k) {
    const int axis = (first + k) % 3;
    if (orient2d_projected(t0, t1, t2, axis, counters) != 0) return axis;
  }
  return -1;
}

/// Closed point-in-triangle test for coplanar p and non-degenerate t, in the
/// projection dropping `axis`.
SNAG_HD_INLINE bool point_in_triangle_2d(Vec3 p, Vec3 t0, Vec3 t1, Vec3 t2, int axis,
                                         PredicateCounters* counters) {
  const int s0 = orient2d_projected(t0, t1, p, axis, counters);
  const int s1 = orient2d_projected(t1, t2, p, axis, counters);
  const int s2 = orient2d_projected(t2, t0, p, axis, counters);
  const bool has_negative = s0 < 0 || s1 < 0 || s2 < 0;
  const bool has_positive = s0 > 0 || s1 > 0 || s2 > 0;
  return !(has_negative && has_positive);
}

/// For c collinear with segment ab (in the projection): is c on the closed
/// segment? Compared coordinate by coordinate, exactly.
SNAG_HD_INLINE bool on_collinear_segment(Vec3 a, Vec3 b, Vec3 c) {
  for (int i = 0; i < 3; ++i) {
    const double lo = a[i] < b[i] ? a[i] : b[i];
    const double hi = a[i] < b[i] ? b[i] : a[i];
    if (c[i] < lo || c[i] > hi) return false;
  }
  return true;
}

/// Closed intersection of coplanar segments ab and cd (non-degenerate
/// segments), in the projection dropping `axis`.
SNAG_HD_INLINE bool segments_intersect_2d(Vec3 a, Vec3 b, Vec3 c, Vec3 d, int axis,
                                          PredicateCounters* counters) {
  const int abc = orient2d_projected(a, b, c, axis, counters);
  const int abd = orient2d_projected(a, b, d, axis, counters);
  if (abc * abd > 0) return false;
  const int cda = orient2d_projected(c, d, a, axis, counters);
  const int cdb = orient2d_projected(c, d, b, axis, counters);
  if (cda * cdb > 0) return false;
  if (abc != 0 || abd != 0 || cda != 0 || cdb != 0) {
    // The lines differ. With no zero sign the segments cross properly. An
    // endpoint on the other segment's line is the only point the lines
    // share, so the segments meet iff it lies on that segment.
    if (abc == 0) return on_collinear_segment(a, b, c);
    if (abd == 0) return on_collinear_segment(a, b, d);
    if (cda == 0) return on_collinear_segment(c, d, a);
    if (cdb == 0) return on_collinear_segment(c, d, b);
    return true;
  }
  // All four points collinear: overlapping ranges.
  return on_collinear_segment(a, b, c) || on_collinear_segment(a, b, d) ||
         on_collinear_segment(c, d, a) || on_collinear_segment(c, d, b);
}

/// Closed intersection of segment ab and a non-degenerate triangle t lying in
/// one plane, in the projection dropping `axis` (non-degenerate for t).
SNAG_HD_INLINE bool coplanar_segment_triangle(Vec3 a, Vec3 b, Vec3 t0, Vec3 t1, Vec3 t2, int axis,
                                              PredicateCounters* counters) {
  return point_in_triangle_2d(a, t0, t1, t2, axis, counters) ||
         point_in_triangle_2d(b, t0, t1, t2, axis, counters) ||
         segments_intersect_2d(a, b, t0, t1, axis, counters) ||
         segments_intersect_2d(a, b, t1, t2, axis, counters) ||
         segments_intersect_2d(a, b, t2, t0, axis, counters);
}

/// Closed intersection of segment ab with non-degenerate triangle t, given
/// side_a = orient3d(t0, t1, t2, a), side_b = orient3d(t0, t1, t2, b) and a
/// projection axis that keeps t non-degenerate.
SNAG_HD_INLINE bool segment_triangle(Vec3 a, Vec3 b, int side_a, int side_b, Vec3 t0, Vec3 t1,
                                     Vec3 t2, int axis, PredicateCounters* counters) {
  if (side_a * side_b > 0) return false;
  if (side_a == 0 && side_b == 0) return coplanar_segment_triangle(a, b, t0, t1, t2, axis, counters);
  // The line ab crosses the plane once, at a point of the closed segment; it
  // lies in the closed triangle iff the line passes on no strict opposite
  // sides of the triangle's edges.
  const int s0 = orient3d(a, b, t0, t1, counters);
  const int s1 = orient3d(a, b, t1, t2, counters);
  if (s0 * s1 < 0) return false;
  const int s2 = orient3d(a, b, t2, t0, counters);
  const bool has_negative = s0 < 0 || s1 < 0 || s2 < 0;
  const bool has_positive = s0 > 0 || s1 > 0 || s2 > 0;
  return !(has_negative && has_positive);
}

/// closed_triangles_intersect given the sides of q's corners to p's plane
/// (orient3d(p[0], p[1], p[2], q[i])), for a caller that has them already.
SNAG_HD_INLINE bool closed_triangles_intersect_with_sides(const Vec3 p[3], int p_axis, const Vec3 q[3], int q_axis,
                                                          const int q_side[3], PredicateCounters* counters) {
  if (q_side[0] * q_side[1] > 0 && q_side[1] * q_side[2] > 0) return false;
  int p_side[3];
  for (int i = 0; i < 3; ++i) p_side[i] = orient3d(q[0], q[1], q[2], p[i], counters);
  if (p_side[0] * p_side[1] > 0 && p_side[1] * p_side[2] > 0) return false;
  for (int i = 0; i < 3; ++i) {
    const int j = i == 2 ? 0 : i + 1;
    if (segment_triangle(p[i], p[j], p_side[i], p_side[j], q[0], q[1], q[2], q_axis, counters))
      return true;
  }
  for (int i = 0; i < 3; ++i) {
    const int j = i == 2 ? 0 : i + 1;
    if (segment_triangle(q[i], q[j], q_side[i], q_side[j], p[0], p[1], p[2], p_axis, counters))
      return true;
  }
  return false;
}

/// Closed intersection of two non-degenerate triangles p and q with their
/// projection axes.
SNAG_HD_INLINE bool closed_triangles_intersect(const Vec3 p[3], int p_axis, const Vec3 q[3], int q_axis,
                                               PredicateCounters* counters) {
  int q_side[3];
  for (int i = 0; i < 3; ++i) q_side[i] = orient3d(p[0], p[1], p[2], q[i], counters);
  return closed_triangles_intersect_with_sides(p, p_axis, q, q_axis, q_side, counters);
}

/// Whether an edge line of the hull of v (nv = 2: a segment, 3: a triangle)
/// has all of u (nu points) strictly on one side and v's own remaining
/// vertex not on that side, in the projection dropping `axis`: then the
/// projected hulls, and so the hulls, are disjoint. Any axis will do; a
/// degenerate projection only finds no line. `v_orientation`: orient2d of
/// v's three points (the side of each edge's remaining vertex, the same for
/// all three edges), 0 for a segment. Edges are tried in the order v0v1,
/// v2v0, v1v2: those at v0 first (put a shared vertex there).
SNAG_HD_INLINE bool separated_by_edge_line_of(const Vec3* v, int nv, int v_orientation, const Vec3* u, int nu,
                                              int axis, PredicateCounters* counters) {
  const int lines = nv == 2 ? 1 : 3;
  for (int line = 0; line < lines; ++line) {
    const int i = line == 0 ? 0 : (line == 1 ? 2 : 1);
    const Vec3 p = v[i], q = v[i + 1 == nv ? 0 : i + 1];
    const int side = orient2d_projected(p, q, u[0], axis, counters);
    if (side == 0 || side == v_orientation) continue;
    bool all = true;
    for (int k = 1; k < nu && all; ++k) all = orient2d_projected(p, q, u[k], axis, counters) == side;
    if (all) return true;
  }
  return false;
}

/// The hulls of v and u (2 or 3 points each) are separated by an edge line
/// of one of them in the projection dropping `axis`.
SNAG_HD_INLINE bool separated_in_projection(const Vec3* v, int nv, const Vec3* u, int nu, int axis,
                                            PredicateCounters* counters) {
  const int v_orientation = nv == 3 ? orient2d_projected(v[0], v[1], v[2], axis, counters) : 0;
  if (separated_by_edge_line_of(v, nv, v_orientation, u, nu, axis, counters)) return true;
  const int u_orientation = nu == 3 ? orient2d_projected(u[0], u[1], u[2], axis, counters) : 0;
  return separated_by_edge_line_of(u, nu, u_orientation, v, nv, axis, counters);
}

/// Triangles (v, a1, a2) and (v, b1, b2) sharing v: whether the line through
/// v and one far vertex of one triangle has that triangle's other far vertex
/// strictly on one side and both far vertices of the other triangle strictly
/// on the other, in the projection dropping `axis`. Then the projected
/// triangles meet only at v (the line holds only v of the second, and the
/// first touches it along its edge from v, which leaves v), so neither far
/// edge meets the other triangle. Fans of a smooth surface are split so.
SNAG_HD_INLINE bool separated_at_shared_vertex(Vec3 v, Vec3 a1, Vec3 a2, Vec3 b1, Vec3 b2, int axis,
                                               PredicateCounters* counters) {
  const Vec3 first_far[2][2] = {{a1, a2}, {b1, b2}};
  for (int side = 0; side < 2; ++side) {
    const Vec3* own = first_far[side];
    const Vec3* other = first_far[1 - side];
    const int orientation = orient2d_projected(v, own[0], own[1], axis, counters);
    if (orientation == 0) continue;
    for (int k = 0; k < 2; ++k) {
      // Line (v, own[k]); own[1 - k] lies on side -orientation for k = 1.
      const int own_side = k == 0 ? orientation : -orientation;
      const int s0 = orient2d_projected(v, own[k], other[0], axis, counters);
      if (s0 != -own_side) continue;
      if (orient2d_projected(v, own[k], other[1], axis, counters) == s0) return true;
    }
  }
  return false;
}

}  // namespace triangle_detail

/// The coordinate axis along which triangle t's floating-point normal is
/// largest: dropping it gives the best conditioned projection.
SNAG_HD_INLINE int dominant_normal_axis(const Vec3 t[3]) {
  const Vec3 n = cross(t[1] - t[0], t[2] - t[0]);
  const double nx = fabs(n.x), ny = fabs(n.y), nz = fabs(n.z);
  return (nx >= ny && nx >= nz) ? 0 : (ny >= nz ? 1 : 2);
}

/// triangles_separated_in_projection in the projection dropping `axis`
/// (any axis is sound; dominant_normal_axis(a) decides the most), for callers
/// that compute each triangle's axis once instead of once per pair.
SNAG_HD_INLINE bool triangles_separated_in_projection_along(int axis, const Vec3 a[3], const std::uint32_t a_ids[3],
                                                            const Vec3 b[3], const std::uint32_t b_ids[3],
                                                            PredicateCounters* counters = nullptr) {
  using namespace triangle_detail;
  const SharedIds shared = shared_ids(a_ids, b_ids);
  const int shared_count = shared.count, a_shared = shared.a_last, b_shared = shared.b_last;
  if (shared_count == 0) return separated_in_projection(a, 3, b, 3, axis, counters);
  if (shared_count == 1) {
    const Vec3 a_from_shared[3] = {a[a_shared], a[(a_shared + 1) % 3], a[(a_shared + 2) % 3]};
    const Vec3 b_from_shared[3] = {b[b_shared], b[(b_shared + 1) % 3], b[(b_shared + 2) % 3]};
    if (separated_at_shared_vertex(a_from_shared[0], a_from_shared[1], a_from_shared[2], b_from_shared[1],
                                   b_from_shared[2], axis, counters))
      return true;
    return separated_in_projection(a_from_shared, 3, b_from_shared + 1, 2, axis, counters) &&
           separated_in_projection(b_from_shared, 3, a_from_shared + 1, 2, axis, counters);
  }
  if (shared_count == 2) {
    const int a_opposite = shared.a_opposite, b_opposite = shared.b_opposite;
    const Vec3 edge0 = a[a_opposite == 2 ? 0 : a_opposite + 1];
    const Vec3 edge1 = a[a_opposite == 0 ? 2 : a_opposite - 1];
    const int r_side = orient2d_projected(edge0, edge1, a[a_opposite], axis, counters);
    if (r_side == 0) return false;
    return r_side * orient2d_projected(edge0, edge1, b[b_opposite], axis, counters) <= 0;
  }
  return false;  // a duplicated face (or ids repeated within a triangle)
}

/// An exact-sign filter in front of triangles_intersect: true only when
/// triangles_intersect(a, a_ids, b, b_ids) is false, shown by 2D orientation
/// signs in the projection along a's dominant normal axis (well conditioned
/// for neighbouring triangles of a smooth surface, where the 3D plane-side
/// tests are nearly zero and need the exact stage):
///   - nothing shared: the projected triangles are separated by an edge line;
///   - one shared vertex: a line through it splits the two triangles
///     (separated_at_shared_vertex), or else each far edge is separated from
///     the other triangle;
///   - a shared edge: the opposite vertices are not strictly on one side of
///     the edge's line, with a's opposite vertex off it (a non-degenerate in
///     the projection). Coplanar, the sides agree in every projection that
///     keeps a non-degenerate; not coplanar, the pair does not intersect.
/// False means "not shown", not "intersecting". Same arguments as
/// triangles_intersect. Does not throw.
SNAG_HD_INLINE bool triangles_separated_in_projection(const Vec3 a[3], const std::uint32_t a_ids[3], const Vec3 b[3],
                                                      const std::uint32_t b_ids[3],
                                                      PredicateCounters* counters = nullptr) {
  return triangles_separated_in_projection_along(dominant_normal_axis(a), a, a_ids, b, b_ids, counters);
}

/// True when the vertices p0, p1, p2 are collinear (exactly), including
/// repeated positions. Such a triangle has no plane and is reported apart.
SNAG_HD_INLINE bool is_degenerate_triangle(Vec3 p0, Vec3 p1, Vec3 p2, PredicateCounters* counters = nullptr) {
  return triangle_detail::projection_axis(p0, p1, p2, counters) < 0;
}

/// triangles_intersect with each triangle's projection axis given:
/// a_axis = triangle_detail::projection_axis(a[0], a[1], a[2], ...), b_axis
/// likewise (-1: degenerate), for callers that compute them once per
/// triangle instead of once per pair. Same result and adjacency.
SNAG_HD_INLINE bool triangles_intersect_with_axes(const Vec3 a[3], const std::uint32_t a_ids[3], int a_axis,
                                                  const Vec3 b[3], const std::uint32_t b_ids[3], int b_axis,
                                                  PredicateCounters* counters = nullptr,
                                                  TriangleAdjacency* adjacency = nullptr) {
  using namespace triangle_detail;
  TriangleAdjacency relation = TriangleAdjacency::none;
  bool result = false;
  if (a_axis < 0 || b_axis < 0) {
    relation = TriangleAdjacency::degenerate;
  } else {
    const SharedIds shared = shared_ids(a_ids, b_ids);
    const int shared_count = shared.count, a_shared = shared.a_last, b_shared = shared.b_last;
    if (shared_count >= 3) {
      relation = TriangleAdjacency::same_vertices;
      result = true;
    } else if (shared_count == 2) {
      relation = TriangleAdjacency::shared_edge;
      const int a_opposite = shared.a_opposite, b_opposite = shared.b_opposite;
      const Vec3 edge0 = a[a_opposite == 2 ? 0 : a_opposite + 1];
      const Vec3 edge1 = a[a_opposite == 0 ? 2 : a_opposite - 1];
      const Vec3 r = a[a_opposite], s = b[b_opposite];
      if (orient3d(a[0], a[1], a[2], s, counters) == 0) {
        // Coplanar: overlap iff r and s are strictly on the same side of the
        // shared edge's line (CGAL's coplanar_orientation == POSITIVE).
        const int r_side = orient2d_projected(edge0, edge1, r, a_axis, counters);
        const int s_side = orient2d_projected(edge0, edge1, s, a_axis, counters);
        result = r_side * s_side > 0;
      }
    } else if (shared_count == 1) {
      relation = TriangleAdjacency::shared_vertex;
      const Vec3 a_far0 = a[(a_shared + 1) % 3], a_far1 = a[(a_shared + 2) % 3];
      const Vec3 b_far0 = b[(b_shared + 1) % 3], b_far1 = b[(b_shared + 2) % 3];
      result = segment_triangle(b_far0, b_far1, orient3d(a[0], a[1], a[2], b_far0, counters),
                                orient3d(a[0], a[1], a[2], b_far1, counters), a[0], a[1], a[2], a_axis,
                                counters) ||
               segment_triangle(a_far0, a_far1, orient3d(b[0], b[1], b[2], a_far0, counters),
                                orient3d(b[0], b[1], b[2], a_far1, counters), b[0], b[1], b[2], b_axis,
                                counters);
    } else {
      result = closed_triangles_intersect(a, a_axis, b, b_axis, counters);
    }
  }
  if (adjacency) *adjacency = relation;
  return result;
}

/// Whether two triangles of one frame intersect, with the shared-feature and
/// degenerate-triangle rules in this file's header (CGAL's self_intersections
/// rules).
///   a, b: [in] the 3 vertex positions of each triangle (any units)
///   a_ids, b_ids: [in] the 3 vertex ids of each triangle, in the same order;
///     ids decide which features are shared (equal positions under different
///     ids are not a shared feature)
///   counters: [in,out] optional predicate counters (null to skip)
///   adjacency: [out] optional, how the two triangles are related
/// Positions must satisfy is_in_exact_range. Does not throw.
SNAG_HD_INLINE bool triangles_intersect(const Vec3 a[3], const std::uint32_t a_ids[3], const Vec3 b[3],
                                        const std::uint32_t b_ids[3], PredicateCounters* counters = nullptr,
                                        TriangleAdjacency* adjacency = nullptr) {
  const int a_axis = triangle_detail::projection_axis(a[0], a[1], a[2], counters);
  const int b_axis = a_axis < 0 ? -1 : triangle_detail::projection_axis(b[0], b[1], b[2], counters);
  return triangles_intersect_with_axes(a, a_ids, a_axis, b, b_ids, b_axis, counters, adjacency);
}

}  // namespace snag
