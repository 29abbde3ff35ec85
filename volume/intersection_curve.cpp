// The segments are CGAL::intersection(Triangle_3, Triangle_3) with the exact
// predicates and exact constructions kernel (CGAL 5.5); the decision, with the
// shared-feature rules of self-intersection, is validate's.
#include "volume/intersection_curve.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>

#include "validate/exact_triangle_intersection.hpp"

namespace snag::volume {

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;

std::array<Vec3, 3> corners(const TriangleMesh& mesh, std::size_t f) {
  const Triangle& t = mesh.triangles[f];
  return {mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]};
}

Kernel::Triangle_3 cgal_triangle(const std::array<Vec3, 3>& c) {
  auto point = [](const Vec3& p) { return Kernel::Point_3(p.x, p.y, p.z); };
  return {point(c[0]), point(c[1]), point(c[2])};
}

struct Face {
  std::size_t id;
  Box box;
};

std::vector<Face> faces_by_x(const TriangleMesh& mesh, const std::vector<std::size_t>& ids) {
  std::vector<Face> faces;
  for (std::size_t f : ids) {
    if (validate::exact_triangle_is_degenerate(corners(mesh, f))) continue;
    faces.push_back({f, triangle_box(mesh, f)});
  }
  std::sort(faces.begin(), faces.end(), [](const Face& p, const Face& q) { return p.box.lo.x < q.box.lo.x; });
  return faces;
}

void add_pair(const TriangleMesh& a, std::size_t fa, const TriangleMesh& b, std::size_t fb, bool same,
              CurveLength& out) {
  const std::array<Vec3, 3> ca = corners(a, fa), cb = corners(b, fb);
  std::array<Index, 3> ids_a = a.triangles[fa], ids_b = b.triangles[fb];
  if (!same) {
    // Two meshes share no vertex: give b's ids their own range.
    for (Index& id : ids_b) id += static_cast<Index>(a.vertices.size());
  }
  if (!validate::exact_triangles_intersect(ca, ids_a, cb, ids_b)) return;
  const auto crossing = CGAL::intersection(cgal_triangle(ca), cgal_triangle(cb));
  if (!crossing) return;
  if (const auto* segment = boost::get<Kernel::Segment_3>(&*crossing)) {
    out.length += std::sqrt(CGAL::to_double(segment->squared_length()));
    ++out.segments;
  } else if (!boost::get<Kernel::Point_3>(&*crossing)) {
    ++out.coplanar;  // a triangle or polygon in the common plane
  }
}

}  // namespace

CurveLength intersection_curve_length(const TriangleMesh& a, const std::vector<std::size_t>& faces_a,
                                      const TriangleMesh& b, const std::vector<std::size_t>& faces_b, bool same) {
  CurveLength out;
  const std::vector<Face> left = faces_by_x(a, faces_a);
  const std::vector<Face> right = same ? left : faces_by_x(b, faces_b);
  // Sweep along x: each face of `left` meets the faces of `right` that start before it ends.
  std::size_t first = 0;
  for (std::size_t i = 0; i < left.size(); ++i) {
    const Face& p = left[i];
    while (first < right.size() && right[first].box.hi.x < p.box.lo.x && !same) ++first;
    for (std::size_t j = same ? i + 1 : first; j < right.size() && right[j].box.lo.x <= p.box.hi.x; ++j) {
      if (!overlaps(p.box, right[j].box)) continue;
      add_pair(a, p.id, same ? a : b, right[j].id, same, out);
    }
  }
  return out;
}

}  // namespace snag::volume
