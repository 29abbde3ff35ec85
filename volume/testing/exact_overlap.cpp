#include "volume/testing/exact_overlap.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>

#include <stdexcept>

namespace snag::volume::testing {

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;

Mesh to_cgal(const TriangleMesh& mesh) {
  Mesh out;
  std::vector<Mesh::Vertex_index> ids;
  for (const Vec3& p : mesh.vertices) ids.push_back(out.add_vertex(Kernel::Point_3(p.x, p.y, p.z)));
  for (const Triangle& f : mesh.triangles) {
    if (out.add_face(ids[f[0]], ids[f[1]], ids[f[2]]) == Mesh::null_face()) {
      throw std::runtime_error("CGAL could not add a face (not a manifold mesh)");
    }
  }
  return out;
}

}  // namespace

double exact_overlap_volume(const TriangleMesh& a, const TriangleMesh& b) {
  Mesh ma = to_cgal(a), mb = to_cgal(b), out;
  if (!CGAL::Polygon_mesh_processing::corefine_and_compute_intersection(ma, mb, out)) {
    throw std::runtime_error("CGAL's corefinement failed");
  }
  return CGAL::to_double(CGAL::Polygon_mesh_processing::volume(out));
}

}  // namespace snag::volume::testing
