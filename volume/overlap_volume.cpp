#include "volume/overlap_volume.hpp"

#include <algorithm>
#include <cmath>

#include <openvdb/tools/LevelSetMeasure.h>
#include <openvdb/tools/LevelSetUtil.h>

#include "volume/closed_level_set.hpp"
#include "volume/region_box.hpp"

namespace snag::volume {

namespace {

constexpr float kHalfWidth = 3;  // voxels: the band levelSetVolume's smeared surface needs

// The CSG intersection of two level sets: max(a, b), as OpenVDB's
// csgIntersection, except where the point is outside both, where the distance
// to the edge the two surfaces meet in is closer to sqrt(a^2 + b^2) than to
// max(a, b). levelSetVolume integrates over the band assuming a distance
// field; with plain max(a, b) the band around the intersection curve is too
// thin and two boxes overlapping 12 voxels across come out 2% large, 0.6% with this.
struct IntersectionOfDistances {
  void operator()(openvdb::CombineArgs<float>& args) const {
    const float a = args.a(), b = args.b();
    args.setResult(a > 0 && b > 0 ? std::sqrt(a * a + b * b) : std::max(a, b));
    args.setResultIsActive(args.aIsActive() || args.bIsActive());
  }
};

openvdb::FloatGrid::Ptr csg_intersection(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  openvdb::FloatGrid::Ptr out = openvdb::FloatGrid::create(a.background());
  out->setTransform(a.transform().copy());
  out->setGridClass(openvdb::GRID_LEVEL_SET);
  out->tree().combine2Extended(a.tree(), b.tree(), IntersectionOfDistances());
  return out;
}

Box active_world_box(const openvdb::FloatGrid& grid) {
  const openvdb::CoordBBox coords = grid.evalActiveVoxelBoundingBox();
  const double h = grid.voxelSize()[0];
  const openvdb::Coord lo = coords.min(), hi = coords.max();
  return {{lo.x() * h, lo.y() * h, lo.z() * h}, {hi.x() * h, hi.y() * h, hi.z() * h}};
}

}  // namespace

OverlapVolume overlap_volume(const TriangleMesh& a, const TriangleMesh& b, const Box& region, double voxel_size) {
  OverlapVolume result;
  result.voxel_size = voxel_size;
  const Box common = intersection(mesh_box(a), mesh_box(b));
  for (int i = 0; i < 3; ++i) {
    if (common.lo[i] > common.hi[i]) return result;
  }
  const Box limit = grown(common, 2 * kHalfWidth * voxel_size);
  auto measure = [&](const VoxelBox& voxels) {
    const Box world = world_box(voxels);
    const WindingColumns winding_a(a, world), winding_b(b, world);
    result.level_set_a = closed_level_set(a, winding_a, voxels, kHalfWidth);
    result.level_set_b = closed_level_set(b, winding_b, voxels, kHalfWidth);
    result.overlap = csg_intersection(*result.level_set_a, *result.level_set_b);
    return !inside_touches_boundary(*result.overlap, voxels);
  };
  result.voxel_size = grow_until_whole(region, limit, voxel_size, kHalfWidth, measure);

  // The overlap's connected pieces: those away from the region are taken out
  // of a copy (their band set outside) before measuring. segmentSDF's own
  // pieces keep too thin a band to measure.
  const Box near_region = grown(region, 2 * result.voxel_size);
  openvdb::FloatGrid::Ptr measured = result.overlap;
  std::vector<openvdb::FloatGrid::Ptr> pieces;
  // Pieces away from the region can only lie outside its box (a third of the time of a measure).
  if (!contains(near_region, active_world_box(*result.overlap))) openvdb::tools::segmentSDF(*result.overlap, pieces);
  for (const openvdb::FloatGrid::Ptr& piece : pieces) {
    if (piece->activeVoxelCount() == 0 || overlaps(active_world_box(*piece), near_region)) continue;
    if (measured == result.overlap) measured = result.overlap->deepCopy();
    auto accessor = measured->getAccessor();
    for (auto voxel = piece->cbeginValueOn(); voxel; ++voxel) {
      accessor.setValueOff(voxel.getCoord(), measured->background());
    }
  }
  if (measured->activeVoxelCount() > 0) result.volume = openvdb::tools::levelSetVolume(*measured);
  result.overlap->setName("overlap");
  return result;
}

}  // namespace snag::volume
