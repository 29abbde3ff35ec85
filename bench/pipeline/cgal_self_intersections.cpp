#include "bench/pipeline/cgal_self_intersections.hpp"

#include "bench/pipeline/process_cpu_time.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <chrono>
#include <iterator>
#include <stdexcept>
#include <utility>

#ifndef CGAL_LINKED_WITH_TBB
#error "CGAL must be linked with TBB (CGAL::TBB_support) for Parallel_if_available_tag to run in parallel"
#endif

namespace snag::bench {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;
}  // namespace

struct CgalSelfIntersectionRunner::Impl {
  Mesh mesh;
  std::vector<Mesh::Vertex_index> vertex_of;  ///< mesh vertex of each scene vertex (the first copy when split)
  std::vector<std::size_t> scene_vertex_of;  ///< when repaired: the scene vertex of each mesh vertex
  bool repaired = false;
};

CgalSelfIntersectionRunner::CgalSelfIntersectionRunner(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  Mesh& mesh = impl_->mesh;
  const std::size_t vertex_count = scene.vertex_count();
  for (std::size_t v = 0; v < vertex_count; ++v) impl_->vertex_of.push_back(mesh.add_vertex(Point(0, 0, 0)));
  for (const Triangle& t : scene.triangles()) {
    const Mesh::Face_index f = mesh.add_face(impl_->vertex_of[t[0]], impl_->vertex_of[t[1]], impl_->vertex_of[t[2]]);
    if (f == Mesh::null_face()) {
      impl_->repaired = true;
      break;
    }
  }
  if (!impl_->repaired) return;
  // The soup repair: points are scene vertex ids; orient_polygon_soup appends
  // a copy of a point for each extra umbrella at a non-manifold vertex.
  std::vector<Point> points(vertex_count, Point(0, 0, 0));
  std::vector<std::vector<std::size_t>> polygons;
  for (const Triangle& t : scene.triangles()) polygons.push_back({t[0], t[1], t[2]});
  // Tag each point with its scene id through its x coordinate so the copies can be traced.
  for (std::size_t v = 0; v < vertex_count; ++v) points[v] = Point(double(v), 0, 0);
  PMP::orient_polygon_soup(points, polygons);
  mesh.clear();
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  if (mesh.number_of_faces() != scene.triangle_count())
    throw std::runtime_error("CGAL's soup repair changed the number of faces");
  impl_->scene_vertex_of.assign(mesh.number_of_vertices(), 0);
  for (Mesh::Vertex_index v : mesh.vertices())
    impl_->scene_vertex_of[std::size_t(v)] = static_cast<std::size_t>(mesh.point(v).x());
}

CgalSelfIntersectionRunner::~CgalSelfIntersectionRunner() = default;

bool CgalSelfIntersectionRunner::repaired() const { return impl_->repaired; }

bool CgalSelfIntersectionRunner::parallel() { return true; }  // enforced by the #error above

CgalSelfIntersections CgalSelfIntersectionRunner::run(const std::vector<Vec3>& positions, double& seconds,
                                                      double& cpu_seconds) {
  Mesh& mesh = impl_->mesh;
  if (impl_->repaired) {
    for (Mesh::Vertex_index v : mesh.vertices()) {
      const Vec3& p = positions[impl_->scene_vertex_of[std::size_t(v)]];
      mesh.point(v) = Point(p.x, p.y, p.z);
    }
  } else {
    for (std::size_t v = 0; v < positions.size(); ++v) {
      const Vec3& p = positions[v];
      mesh.point(impl_->vertex_of[v]) = Point(p.x, p.y, p.z);
    }
  }
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> found;
  const double cpu_start = process_cpu_seconds();
  const auto start = std::chrono::steady_clock::now();
  PMP::self_intersections<CGAL::Parallel_if_available_tag>(mesh, std::back_inserter(found));
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  cpu_seconds = process_cpu_seconds() - cpu_start;
  CgalSelfIntersections result;
  for (const auto& [f, g] : found) {
    const Index a = Index(std::size_t(f)), b = Index(std::size_t(g));
    if (a == b)
      result.degenerate_faces.push_back(a);
    else
      result.pairs.push_back({std::min(a, b), std::max(a, b)});
  }
  std::sort(result.pairs.begin(), result.pairs.end());
  std::sort(result.degenerate_faces.begin(), result.degenerate_faces.end());
  return result;
}

}  // namespace snag::bench
