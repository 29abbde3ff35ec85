// How far an open mesh (cloth) reaches into a closed one (a body) near one
// intersection region: the depth of its deepest point by the body's signed
// distance, and the area of it that lies inside.
#pragma once

#include <openvdb/openvdb.h>

#include <vector>

#include "volume/triangle_mesh.hpp"
#include "volume/vertex_faces.hpp"

namespace snag::volume {

struct Penetration {
  double depth = 0;       ///< scene units, >= 0: the largest distance inside the closed mesh
  double area = 0;        ///< scene units squared: of the open mesh inside the closed one
  double voxel_size = 0;  ///< the one used
  openvdb::FloatGrid::Ptr level_set;  ///< the closed mesh's signed distance on the box used
};

/// The part of `open` inside `closed` that is connected (through shared
/// vertices) to the faces `seeds` of `open` (the region's faces on it),
/// measured on the closed mesh's level set with voxels of `voxel_size`: every
/// face of that part is cut into sub-triangles no larger than a voxel, the
/// signed distance is sampled (trilinear) at their corners, and the area where
/// its linear interpolant is negative is summed; the depth is the largest
/// negated distance sampled. The box grows from `region` (the region's bounds)
/// until the part lies inside it, within the closed mesh's bounds.
/// `open_faces`: vertex_faces() of `open`.
Penetration penetration(const TriangleMesh& open, const VertexFaces& open_faces, const std::vector<std::size_t>& seeds,
                        const TriangleMesh& closed, const Box& region, double voxel_size);

/// The area of the part of a triangle of area `area` where the linear function
/// with corner values f0, f1, f2 is negative.
double area_below_zero(double area, double f0, double f1, double f2);

}  // namespace snag::volume
