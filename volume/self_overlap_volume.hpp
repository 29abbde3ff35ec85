// The self-overlap of one closed mesh near an intersection region: the volume
// where its winding number is two or more (a mesh folded through itself
// encloses that space twice). OpenVDB has no winding numbers, so they come
// from WindingColumns: exact along each line of voxel centres parallel to x,
// sampled at the voxel centres across: the error is second order in the voxel
// size on curved surfaces, but up to a voxel's width on each face of a box
// aligned with the axes.
#pragma once

#include <openvdb/openvdb.h>

#include "volume/triangle_mesh.hpp"

namespace snag::volume {

struct SelfOverlapVolume {
  double volume = 0;      ///< scene units cubed
  double voxel_size = 0;  ///< the one used
  /// Fog volume: each voxel's fraction (0 to 1) inside the self-overlap.
  openvdb::FloatGrid::Ptr overlap;
};

/// The volume where the winding number of `mesh` is at least two near the
/// region box `region`, with voxels of `voxel_size` (scene units); the box
/// grows as in overlap_volume() until the self-overlap does not reach its
/// sides, within the mesh's bounds.
SelfOverlapVolume self_overlap_volume(const TriangleMesh& mesh, const Box& region, double voxel_size);

}  // namespace snag::volume
