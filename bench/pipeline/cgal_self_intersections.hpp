// CGAL's static self-intersection detection on a snag scene, the reference
// snag's intersections() is timed and compared against:
// CGAL::Polygon_mesh_processing::self_intersections with
// CGAL::Parallel_if_available_tag on a Surface_mesh built once from the
// scene's global triangles (face i of the mesh is global triangle i).
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "libcd/broad_phase/candidates.hpp"
#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/scene.hpp"

namespace snag::bench {

/// What self_intersections reports for one frame.
struct CgalSelfIntersections {
  std::vector<TrianglePair> pairs;      ///< intersecting faces a < b, sorted
  std::vector<Index> degenerate_faces;  ///< faces CGAL reports as (f, f): collinear corners, sorted
};

class CgalSelfIntersectionRunner {
 public:
  /// Builds the mesh for the scene's topology. When a triangle cannot be
  /// added as it is (a non-manifold vertex or edge, or inconsistent
  /// orientation), the mesh is built with CGAL's polygon-soup repair instead,
  /// which keeps face ids but may split vertices; repaired() then says so.
  explicit CgalSelfIntersectionRunner(const Scene& scene);
  ~CgalSelfIntersectionRunner();

  /// True when the mesh needed the soup repair (vertex sharing may differ
  /// from the scene's, and so may the shared-feature rules).
  bool repaired() const;
  /// Whether CGAL was compiled with TBB, so that Parallel_if_available_tag is parallel.
  static bool parallel();

  /// Sets the mesh's points to `positions` (#V) and runs self_intersections.
  /// `seconds` receives the wall time of the self_intersections call alone,
  /// `cpu_seconds` the process's CPU time (all threads) during it.
  CgalSelfIntersections run(const std::vector<Vec3>& positions, double& seconds, double& cpu_seconds);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace snag::bench
