// The signed distance level set of a closed mesh inside a box of voxels.
#pragma once

#include <openvdb/openvdb.h>

#include "volume/triangle_mesh.hpp"
#include "volume/voxel_box.hpp"
#include "volume/winding_columns.hpp"

namespace snag::volume {

/// A level set (negative inside) of the closed `mesh` on the voxels of `box`
/// only, from the triangles near the box: the distance to them (exact within
/// `half_width` voxels of the surface, where voxels are active) and the sign
/// from the winding number (`winding`, built over a box that holds `box`),
/// not from OpenVDB's flood fill, so that the triangles can be cut to the box. Voxels
/// inside the box and farther than the band are inactive at -half_width *
/// voxel_size inside, +half_width * voxel_size outside; everything outside the
/// box is outside. Grid class: level set, world units.
openvdb::FloatGrid::Ptr closed_level_set(const TriangleMesh& mesh, const WindingColumns& winding, const VoxelBox& box,
                                         float half_width);

/// Whether the grid is negative on a voxel of the box's outer layer: a shape
/// that the box cut, so that the box must grow to hold all of it.
bool inside_touches_boundary(const openvdb::FloatGrid& grid, const VoxelBox& box);

}  // namespace snag::volume
