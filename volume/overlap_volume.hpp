// The overlap volume of two closed meshes near one intersection region: their
// level sets on a box around the region, their CSG intersection (the larger
// distance; the distance to the edge where both are outside), and OpenVDB's
// levelSetVolume of the pieces of the overlap that meet the region.
#pragma once

#include <openvdb/openvdb.h>

#include "volume/triangle_mesh.hpp"

namespace snag::volume {

struct OverlapVolume {
  double volume = 0;          ///< scene units cubed
  double voxel_size = 0;      ///< the one used (larger than asked when the box would hold too many voxels)
  openvdb::FloatGrid::Ptr level_set_a, level_set_b, overlap;  ///< on the box the overlap needed; null when none
};

/// The volume inside both closed meshes `a` and `b` near the region box
/// `region` (the bounds of the region's faces), with voxels of `voxel_size`
/// (scene units). The box starts as the region's plus a margin and doubles its
/// margin until no part of the overlap reaches its sides, so an overlap that
/// reaches far past the intersection curve (a lens between two spheres) is
/// measured whole; it never grows past the two meshes' common bounds. Of the
/// overlap's connected pieces, those that meet the region box count.
OverlapVolume overlap_volume(const TriangleMesh& a, const TriangleMesh& b, const Box& region, double voxel_size);

}  // namespace snag::volume
