#include "volume/self_overlap_volume.hpp"

#include <algorithm>

#include "volume/region_box.hpp"
#include "volume/voxel_box.hpp"
#include "volume/winding_columns.hpp"

namespace snag::volume {

SelfOverlapVolume self_overlap_volume(const TriangleMesh& mesh, const Box& region, double voxel_size) {
  SelfOverlapVolume result;
  const Box limit = grown(mesh_box(mesh), 2 * voxel_size);
  auto measure = [&](const VoxelBox& voxels) {
    const double h = voxels.voxel_size;
    const WindingColumns winding(mesh, world_box(voxels));
    result.overlap = openvdb::FloatGrid::create(0);
    result.overlap->setTransform(voxel_transform(h));
    result.overlap->setGridClass(openvdb::GRID_FOG_VOLUME);
    auto accessor = result.overlap->getAccessor();
    result.volume = 0;
    bool touches = false;
    std::vector<Crossing> line;
    const openvdb::Coord lo = voxels.coords.min(), hi = voxels.coords.max();
    for (openvdb::Int32 k = lo.z(); k <= hi.z(); ++k) {
      for (openvdb::Int32 j = lo.y(); j <= hi.y(); ++j) {
        winding.crossings(j * h, k * h, line);
        if (line.empty()) continue;
        // Each voxel's part of the line, [x - h/2, x + h/2], exact along x.
        double row = 0;
        for (openvdb::Int32 i = lo.x(); i <= hi.x(); ++i) {
          const double inside = length_with_winding(line, (i - 0.5) * h, (i + 0.5) * h, 2);
          if (inside <= 0) continue;
          row += inside;
          accessor.setValue(openvdb::Coord(i, j, k), static_cast<float>(inside / h));
          if (i == lo.x() || i == hi.x()) touches = true;
        }
        if (row > 0 && (j == lo.y() || j == hi.y() || k == lo.z() || k == hi.z())) touches = true;
        result.volume += row * h * h;
      }
    }
    return !touches;
  };
  result.voxel_size = grow_until_whole(region, limit, voxel_size, 1, measure);
  return result;
}

}  // namespace snag::volume
