// One intersection region's measure: which one its objects call for (by
// their closedness), at the region's voxel size and at twice it for the
// error estimate, and the grids it made for the .vdb export.
#pragma once

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

#include "libcd/scene/object.hpp"
#include "report/records.hpp"
#include "volume/triangle_mesh.hpp"
#include "volume/vertex_faces.hpp"

namespace snag::volume {

/// Whether an object bounds a volume: closed when it has no boundary edge and
/// no non-manifold edge (the counts snag-info prints).
struct ObjectShape {
  std::string name;
  EdgeCounts edges;
  bool closed() const { return edges.boundary == 0 && edges.non_manifold == 0; }
};
ObjectShape object_shape(const Object& object);

/// One side of a region: an object's mesh in the region's frame.
struct RegionSide {
  const TriangleMesh* mesh = nullptr;
  const VertexFaces* vertex_faces = nullptr;  ///< of `mesh`
  ObjectShape shape;
  std::vector<std::size_t> faces;             ///< the region's faces on it
};

struct NamedGrid {
  std::string name;
  openvdb::FloatGrid::Ptr grid;
};

struct MeasuredRegion {
  report::RegionMeasures measures;
  std::vector<NamedGrid> grids;  ///< "<object>" level sets and "region_<id>_..." overlaps
};

/// Measures region `region` (its id, bounds and objects) between `a` and `b`
/// (the same side twice for a self-intersection region):
/// - two closed objects: overlap_volume(); one closed object: self_overlap_volume();
/// - an open and a closed object: penetration() of the open one;
/// - otherwise intersection_curve_length().
/// `voxel_size` 0 takes region_voxel_size(). Volumes, depth and area are
/// measured again at twice the voxel size; the change is the error estimate.
MeasuredRegion measure_region(const report::RegionRecord& region, const RegionSide& a, const RegionSide& b,
                              double voxel_size);

/// The default voxel size of a region (scene units): half the mean edge length
/// of its faces, and no more than a sixteenth of its box's longest side (large
/// flat faces); that sixteenth alone when it has no faces.
double region_voxel_size(const RegionSide& a, const RegionSide& b, bool self, const Box& bounds);

/// The faces of `mesh` whose boxes meet `bounds`: a region's faces when the
/// report does not list them (scanned with --events none).
std::vector<std::size_t> faces_near(const TriangleMesh& mesh, const Box& bounds);

}  // namespace snag::volume
