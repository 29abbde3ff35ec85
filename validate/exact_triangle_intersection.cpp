// Exact static triangle–triangle intersection.
//
// Reference: the shared-feature rules follow do_faces_intersect() in
// CGAL/Polygon_mesh_processing/self_intersections.h (CGAL 5.5); the geometric
// tests are CGAL's exact-predicate do_intersect for Triangle_3/Triangle_3 and
// Triangle_3/Segment_3 (O. Devillers, P. Guigue, "Faster triangle-triangle
// intersection tests", INRIA RR-4488, 2002).
#include "validate/exact_triangle_intersection.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <cassert>

namespace snag::validate {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;

Point to_point(const Vec3& p) { return Point(p.x, p.y, p.z); }

}  // namespace

bool exact_triangle_is_degenerate(const std::array<Vec3, 3>& corners) {
  return CGAL::collinear(to_point(corners[0]), to_point(corners[1]), to_point(corners[2]));
}

bool exact_triangles_intersect(const std::array<Vec3, 3>& a, const std::array<Index, 3>& a_ids,
                               const std::array<Vec3, 3>& b, const std::array<Index, 3>& b_ids) {
  assert(!exact_triangle_is_degenerate(a) && !exact_triangle_is_degenerate(b));
  assert(a_ids[0] != a_ids[1] && a_ids[1] != a_ids[2] && a_ids[0] != a_ids[2]);
  assert(b_ids[0] != b_ids[1] && b_ids[1] != b_ids[2] && b_ids[0] != b_ids[2]);

  // Which corner of b, if any, each corner of a shares.
  int shared_in_b[3] = {-1, -1, -1};
  int shared_count = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (a_ids[i] == b_ids[j]) {
        shared_in_b[i] = j;
        ++shared_count;
      }

  if (shared_count >= 2) {
    // Shared edge u–v; w is a's third corner, x is b's.
    int w = 0;
    while (shared_in_b[w] >= 0) ++w;
    int x = 0;
    while (x == shared_in_b[0] || x == shared_in_b[1] || x == shared_in_b[2]) ++x;
    const Point u = to_point(a[(w + 1) % 3]), v = to_point(a[(w + 2) % 3]);
    const Point pw = to_point(a[w]), px = to_point(b[x]);
    return CGAL::coplanar(u, v, pw, px) && CGAL::coplanar_orientation(u, v, pw, px) == CGAL::POSITIVE;
  }

  const Triangle ta(to_point(a[0]), to_point(a[1]), to_point(a[2]));
  const Triangle tb(to_point(b[0]), to_point(b[1]), to_point(b[2]));
  if (shared_count == 1) {
    int i = 0;
    while (shared_in_b[i] < 0) ++i;
    const int j = shared_in_b[i];
    const Segment opposite_a(to_point(a[(i + 1) % 3]), to_point(a[(i + 2) % 3]));
    const Segment opposite_b(to_point(b[(j + 1) % 3]), to_point(b[(j + 2) % 3]));
    return CGAL::do_intersect(ta, opposite_b) || CGAL::do_intersect(tb, opposite_a);
  }
  return CGAL::do_intersect(ta, tb);
}

}  // namespace snag::validate
