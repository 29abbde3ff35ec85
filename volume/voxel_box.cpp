#include "volume/voxel_box.hpp"

#include <cmath>

namespace snag::volume {

VoxelBox voxel_box(const Box& box, double voxel_size) {
  VoxelBox voxels;
  voxels.voxel_size = voxel_size;
  for (int i = 0; i < 3; ++i) {
    voxels.coords.min()[i] = static_cast<openvdb::Int32>(std::floor(box.lo[i] / voxel_size)) - 1;
    voxels.coords.max()[i] = static_cast<openvdb::Int32>(std::ceil(box.hi[i] / voxel_size)) + 1;
  }
  return voxels;
}

Box world_box(const VoxelBox& voxels) {
  const openvdb::Coord lo = voxels.coords.min(), hi = voxels.coords.max();
  const double h = voxels.voxel_size;
  return {{lo.x() * h, lo.y() * h, lo.z() * h}, {hi.x() * h, hi.y() * h, hi.z() * h}};
}

double voxel_count(const VoxelBox& voxels) {
  const openvdb::Coord d = voxels.coords.dim();
  return static_cast<double>(d.x()) * d.y() * d.z();
}

openvdb::math::Transform::Ptr voxel_transform(double voxel_size) {
  return openvdb::math::Transform::createLinearTransform(voxel_size);
}

}  // namespace snag::volume
