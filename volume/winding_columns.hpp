// Winding numbers of a triangle mesh along lines parallel to the x axis.
//
// OpenVDB's meshToVolume decides inside and outside by flood fill, which needs
// the whole closed mesh and cannot count how many times a point is enclosed;
// here each line (y, z) is crossed with the mesh and the signed crossings are
// summed, so the winding number of every point on the line is known at once:
// +1 inside a closed mesh, 2 or more where a closed mesh overlaps itself.
// Triangles are projected on the (y, z) plane and a line belongs to a
// triangle by the top-left rule of rasterisers (edge functions evaluated on
// each edge's canonically ordered ends), so a line through a shared edge or
// vertex crosses exactly one of the triangles that meet there.
#pragma once

#include <cstddef>
#include <vector>

#include "volume/triangle_mesh.hpp"

namespace snag::volume {

/// Where a line parallel to x crosses the mesh: x (scene units) and the sign
/// of the triangle's normal's x component (oriented so that +1 leaves the
/// inside of a positively oriented closed mesh).
struct Crossing {
  double x = 0;
  int sign = 0;
};

class WindingColumns {
 public:
  /// Indexes the triangles of `mesh` whose (y, z) projection meets the box's
  /// [lo.y, hi.y] x [lo.z, hi.z]; lines are then queried inside that range.
  /// The mesh's orientation is taken from its signed volume, so inward-facing
  /// closed meshes count +1 inside too. `mesh` must outlive this object.
  WindingColumns(const TriangleMesh& mesh, const Box& box);

  /// The crossings of the line {(t, y, z)}, sorted by x.
  void crossings(double y, double z, std::vector<Crossing>& out) const;

  /// The winding number of point p (its line's crossings beyond p.x, summed).
  int winding_number(const Vec3& p) const;

 private:
  std::size_t cell_of(double y, double z) const;

  const TriangleMesh& mesh_;
  int orientation_ = 1;
  double y0_ = 0, z0_ = 0, cell_ = 1;
  std::size_t ny_ = 1, nz_ = 1;
  std::vector<std::size_t> cell_start_;   // CSR: triangles of cell c are cell_triangles_[cell_start_[c] ..]
  std::vector<std::size_t> cell_triangles_;
};

/// The winding number at x of a line with sorted `crossings`.
int winding_at(const std::vector<Crossing>& crossings, double x);

/// The total length of [x0, x1] where the winding number of a line with
/// sorted `crossings` is at least `min_winding`.
double length_with_winding(const std::vector<Crossing>& crossings, double x0, double x1, int min_winding);

}  // namespace snag::volume
