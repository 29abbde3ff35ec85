#include "volume/region_box.hpp"

#include <algorithm>

namespace snag::volume {

double grow_until_whole(const Box& region, const Box& limit, double voxel_size, float band,
                        const std::function<bool(const VoxelBox&)>& measure) {
  double margin = std::max(0.25 * longest_side(region), (band + 1) * voxel_size);
  for (;;) {
    Box box = intersection(grown(region, margin), limit);
    for (int i = 0; i < 3; ++i) {
      // A region outside the limit (its faces only touch): measure at the limit's side.
      if (box.lo[i] > box.hi[i]) box.lo[i] = box.hi[i] = std::clamp(region.lo[i], limit.lo[i], limit.hi[i]);
    }
    VoxelBox voxels = voxel_box(box, voxel_size);
    while (voxel_count(voxels) > kMaxBoxVoxels) {
      voxel_size *= 2;
      voxels = voxel_box(box, voxel_size);
    }
    const bool whole = measure(voxels);
    if (whole || contains(box, limit)) return voxel_size;
    margin *= 2;
  }
}

}  // namespace snag::volume
