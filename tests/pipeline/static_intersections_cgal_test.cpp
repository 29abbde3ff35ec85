// Oracle test of the CPU pipeline's static detection (broad phase, then the
// exact-sign triangle test) against CGAL's
// Polygon_mesh_processing::self_intersections, pair for pair, on every frame
// of the cloth_ball sample with both objects in one mesh (global vertex ids).
// Degenerate faces: CGAL reports them as (f, f) and pairs them with nothing;
// the triangle test declines them (triangle_triangle.hpp) and the pipeline
// must not report them either.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <iterator>
#include <utility>
#include <vector>

#include "libcd/narrow_phase/triangle_triangle.hpp"
#include "libcd/pipeline/backend.hpp"
#include "tests/pipeline/sample_cache.hpp"

namespace snag::test {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;
using FacePair = std::pair<Index, Index>;

/// The scene as one Surface_mesh whose vertex and face indices are the
/// scene's global ids.
Mesh mesh_of(const Scene& scene, const std::vector<Vec3>& x) {
  Mesh mesh;
  for (const Vec3& p : x) mesh.add_vertex(Point(p.x, p.y, p.z));
  for (const Triangle& t : scene.triangles()) {
    const Mesh::Face_index f = mesh.add_face(Mesh::Vertex_index(t[0]), Mesh::Vertex_index(t[1]), Mesh::Vertex_index(t[2]));
    EXPECT_EQ(std::size_t(f), mesh.number_of_faces() - 1) << "face not added: non-manifold or inconsistent orientation";
  }
  return mesh;
}

struct CgalFrame {
  std::vector<FacePair> pairs;  ///< a < b, sorted
  std::vector<Index> degenerate;
};

CgalFrame cgal_self_intersections(const Mesh& mesh) {
  std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> found;
  PMP::self_intersections(mesh, std::back_inserter(found));
  CgalFrame frame;
  for (const auto& [f, g] : found) {
    const Index a = Index(f), b = Index(g);
    if (a == b) {
      frame.degenerate.push_back(a);
    } else {
      frame.pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
  }
  std::sort(frame.pairs.begin(), frame.pairs.end());
  std::sort(frame.degenerate.begin(), frame.degenerate.end());
  return frame;
}

TEST(PipelineStaticIntersections, EqualCgalSelfIntersectionsOnEveryFrameOfTheSample) {
  auto source = open_sample_cache();
  const Scene& scene = source->scene();
  ASSERT_EQ(source->frame_count(), 40u);
  auto backend = make_cpu_backend();
  BackendSettings settings;
  settings.threads = 2;
  backend->bind(scene, settings);

  std::vector<Vec3> x = read_positions(*source, 0);
  Mesh mesh = mesh_of(scene, x);
  ASSERT_EQ(mesh.number_of_faces(), scene.triangle_count());

  std::size_t total_pairs = 0, frames_with_pairs = 0, cloth_body_pairs = 0;
  const Index body_first_face = scene.triangle_offset(1);
  for (std::size_t i = 0; i < source->frame_count(); ++i) {
    SCOPED_TRACE("frame " + std::to_string(i));
    source->read_frame(i, x);
    for (Mesh::Vertex_index v : mesh.vertices()) mesh.point(v) = Point(x[v].x, x[v].y, x[v].z);
    const CgalFrame expected = cgal_self_intersections(mesh);

    std::vector<Event> events;
    backend->intersections(x, events);
    std::vector<FacePair> ours;
    for (const Event& e : events) {
      EXPECT_EQ(e.kind, EventKind::kIntersection);
      EXPECT_EQ(e.type, ContactType::kTriangleTriangle);
      EXPECT_LT(e.a, e.b);
      ours.emplace_back(e.a, e.b);
    }
    EXPECT_TRUE(std::is_sorted(ours.begin(), ours.end()));

    std::vector<FacePair> missed, extra;
    std::set_difference(expected.pairs.begin(), expected.pairs.end(), ours.begin(), ours.end(),
                        std::back_inserter(missed));
    std::set_difference(ours.begin(), ours.end(), expected.pairs.begin(), expected.pairs.end(),
                        std::back_inserter(extra));
    EXPECT_TRUE(missed.empty()) << missed.size() << " CGAL pairs missed, first (" << missed[0].first << ", "
                                << missed[0].second << ")";
    EXPECT_TRUE(extra.empty()) << extra.size() << " pairs CGAL does not report, first (" << extra[0].first << ", "
                               << extra[0].second << ")";

    // Degenerate faces, decided the same way on both sides; none reported in a pair.
    std::vector<Index> degenerate;
    for (Index f = 0; f < scene.triangle_count(); ++f) {
      const Triangle& t = scene.triangles()[f];
      if (is_degenerate_triangle(x[t[0]], x[t[1]], x[t[2]])) degenerate.push_back(f);
    }
    EXPECT_EQ(degenerate, expected.degenerate);
    for (const FacePair& p : ours) {
      EXPECT_FALSE(std::binary_search(degenerate.begin(), degenerate.end(), p.first));
      EXPECT_FALSE(std::binary_search(degenerate.begin(), degenerate.end(), p.second));
    }

    total_pairs += ours.size();
    frames_with_pairs += !ours.empty();
    for (const FacePair& p : ours) cloth_body_pairs += p.first < body_first_face && p.second >= body_first_face;
  }
  // The sample is not trivial: samples/README.md counts self-intersections
  // from frame 16 on (25 frames) and cloth-body ones in 7 frames.
  EXPECT_GE(frames_with_pairs, 25u);
  EXPECT_GT(cloth_body_pairs, 0u);
  std::cout << "[ sample ] " << total_pairs << " intersecting pairs over 40 frames, " << cloth_body_pairs
            << " cloth-body, in " << frames_with_pairs << " frames\n";
}

}  // namespace
}  // namespace snag::test
