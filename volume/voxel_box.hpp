// The voxels a measure works in: a box of index coordinates on a grid whose
// voxel ijk has its centre at ijk * voxel_size (scene units), the transform
// every grid of one measure shares so that OpenVDB can combine them.
#pragma once

#include <openvdb/openvdb.h>

#include "volume/triangle_mesh.hpp"

namespace snag::volume {

struct VoxelBox {
  openvdb::CoordBBox coords;  ///< inclusive index range
  double voxel_size = 1;      ///< scene units
};

/// The voxels whose centres cover `box` (one more on each side).
VoxelBox voxel_box(const Box& box, double voxel_size);
/// The box of the voxel centres, in scene units.
Box world_box(const VoxelBox& voxels);
/// The number of voxels in the box.
double voxel_count(const VoxelBox& voxels);
/// The transform of every grid on this voxel size.
openvdb::math::Transform::Ptr voxel_transform(double voxel_size);

/// The most voxels a measure's box may hold; a region that would need more is
/// measured with a larger voxel size (the report says which).
constexpr double kMaxBoxVoxels = 160.0 * 160.0 * 160.0;

}  // namespace snag::volume
