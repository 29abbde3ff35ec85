// The box a region's measure runs in, grown until the measured shape fits.
#pragma once

#include <functional>

#include "volume/voxel_box.hpp"

namespace snag::volume {

/// Runs `measure` on voxel boxes around `region`: first the region's box
/// plus a margin (a quarter of its longest side, at least `band` + 1 voxels),
/// then with the margin doubled each time `measure` returns false (the shape
/// reached the box's sides), clipped to `limit`; the box that holds all of
/// `limit` is the last. Where a box would hold more than kMaxBoxVoxels the
/// voxel size doubles. Returns the voxel size of the last run.
double grow_until_whole(const Box& region, const Box& limit, double voxel_size, float band,
                        const std::function<bool(const VoxelBox&)>& measure);

}  // namespace snag::volume
