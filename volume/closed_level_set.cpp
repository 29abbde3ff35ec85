#include "volume/closed_level_set.hpp"

#include <openvdb/tools/MeshToVolume.h>

#include <unordered_map>

namespace snag::volume {

void mesh_near_box(const TriangleMesh& mesh, const Box& box, std::vector<openvdb::Vec3s>& points,
                   std::vector<openvdb::Vec3I>& triangles) {
  points.clear();
  triangles.clear();
  std::unordered_map<Index, openvdb::Index32> local;
  auto point_of = [&](Index v) {
    auto [it, added] = local.emplace(v, static_cast<openvdb::Index32>(points.size()));
    if (added) {
      const Vec3& p = mesh.vertices[v];
      points.emplace_back(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
    }
    return it->second;
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!overlaps(triangle_box(mesh, t), box)) continue;
    const Triangle& f = mesh.triangles[t];
    triangles.emplace_back(point_of(f[0]), point_of(f[1]), point_of(f[2]));
  }
}

openvdb::FloatGrid::Ptr closed_level_set(const TriangleMesh& mesh, const WindingColumns& winding, const VoxelBox& box,
                                         float half_width) {
  const double h = box.voxel_size;
  const float background = static_cast<float>(half_width * h);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  mesh_near_box(mesh, grown(world_box(box), (half_width + 1) * h), points, triangles);
  openvdb::FloatGrid::Ptr grid;
  if (triangles.empty()) {
    grid = openvdb::FloatGrid::create(background);
    grid->setTransform(voxel_transform(h));
  } else {
    grid = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(*voxel_transform(h), points, triangles, {},
                                                                           half_width);
  }
  grid->tree().clip(box.coords);
  grid->setGridClass(openvdb::GRID_LEVEL_SET);

  // The sign, one line of voxels at a time.
  auto accessor = grid->getAccessor();
  std::vector<Crossing> line;
  const openvdb::Coord lo = box.coords.min(), hi = box.coords.max();
  for (openvdb::Int32 k = lo.z(); k <= hi.z(); ++k) {
    for (openvdb::Int32 j = lo.y(); j <= hi.y(); ++j) {
      winding.crossings(j * h, k * h, line);
      if (line.empty()) continue;
      // Crossings beyond x, summed: walk x upwards, dropping crossings passed.
      int beyond = 0;
      for (const Crossing& c : line) beyond += c.sign;
      std::size_t next = 0;
      for (openvdb::Int32 i = lo.x(); i <= hi.x(); ++i) {
        const double x = i * h;
        while (next < line.size() && line[next].x <= x) beyond -= line[next++].sign;
        if (beyond < 1) continue;
        const openvdb::Coord ijk(i, j, k);
        float value;
        if (accessor.probeValue(ijk, value)) {
          accessor.setValue(ijk, -value);
        } else {
          accessor.setValueOff(ijk, -background);
        }
      }
    }
  }
  return grid;
}

bool inside_touches_boundary(const openvdb::FloatGrid& grid, const VoxelBox& box) {
  auto accessor = grid.getConstAccessor();
  const openvdb::Coord lo = box.coords.min(), hi = box.coords.max();
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (openvdb::Int32 side : {lo[axis], hi[axis]}) {
      openvdb::Coord ijk;
      ijk[axis] = side;
      for (ijk[u] = lo[u]; ijk[u] <= hi[u]; ++ijk[u]) {
        for (ijk[v] = lo[v]; ijk[v] <= hi[v]; ++ijk[v]) {
          if (accessor.getValue(ijk) < 0) return true;
        }
      }
    }
  }
  return false;
}

}  // namespace snag::volume
