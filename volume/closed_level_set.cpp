#include "volume/closed_level_set.hpp"

#include <algorithm>
#include <cmath>

#include "volume/point_triangle_distance.hpp"

namespace snag::volume {

namespace {

// Squared distances (scene units squared) to the triangles of `mesh`, on
// every voxel of `box`, exact where below band^2 and band^2 elsewhere; x
// varies fastest. OpenVDB's meshToUnsignedDistanceField computes the same
// band but its set-up alone took 0.12 s for 5,120 triangles on 87,000 voxels
// (longer than CGAL's whole corefinement of the pair); boxes here are small
// and dense, so a plain loop over each triangle's voxels does.
std::vector<float> squared_distances(const TriangleMesh& mesh, const VoxelBox& box, double band) {
  const double h = box.voxel_size;
  const openvdb::Coord lo = box.coords.min(), dim = box.coords.dim();
  const float far = static_cast<float>(band * band);
  std::vector<float> d2(static_cast<std::size_t>(dim.x()) * dim.y() * dim.z(), far);
  const Box reach = grown(world_box(box), band);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Box tb = triangle_box(mesh, t);
    if (!overlaps(tb, reach)) continue;
    const Triangle& f = mesh.triangles[t];
    const Vec3 a = mesh.vertices[f[0]], b = mesh.vertices[f[1]], c = mesh.vertices[f[2]];
    const Vec3 normal = cross(b - a, c - a);
    const double normal_length = std::sqrt(squared_norm(normal));
    int from[3], to[3];
    for (int i = 0; i < 3; ++i) {
      from[i] = std::max(lo[i], static_cast<int>(std::ceil((tb.lo[i] - band) / h)));
      to[i] = std::min(lo[i] + dim[i] - 1, static_cast<int>(std::floor((tb.hi[i] + band) / h)));
    }
    for (int k = from[2]; k <= to[2]; ++k) {
      for (int j = from[1]; j <= to[1]; ++j) {
        const std::size_t row = (static_cast<std::size_t>(k - lo[2]) * dim.y() + (j - lo[1])) * dim.x();
        for (int i = from[0]; i <= to[0]; ++i) {
          const Vec3 p{i * h, j * h, k * h};
          // Far from the triangle's plane: far from the triangle.
          if (normal_length > 0 && std::abs(dot(p - a, normal)) >= band * normal_length) continue;
          float& slot = d2[row + (i - lo[0])];
          const double distance2 = squared_distance_to_triangle(p, a, b, c);
          if (distance2 < slot) slot = static_cast<float>(distance2);
        }
      }
    }
  }
  return d2;
}

}  // namespace

openvdb::FloatGrid::Ptr closed_level_set(const TriangleMesh& mesh, const WindingColumns& winding, const VoxelBox& box,
                                         float half_width) {
  const double h = box.voxel_size;
  const double band = half_width * h;
  const float background = static_cast<float>(band);
  const std::vector<float> d2 = squared_distances(mesh, box, band);
  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(background);
  grid->setTransform(voxel_transform(h));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);

  // Distances in the band, and the sign, one line of voxels at a time.
  auto accessor = grid->getAccessor();
  std::vector<Crossing> line;
  const openvdb::Coord lo = box.coords.min(), hi = box.coords.max(), dim = box.coords.dim();
  const float far = static_cast<float>(band * band);
  for (openvdb::Int32 k = lo.z(); k <= hi.z(); ++k) {
    for (openvdb::Int32 j = lo.y(); j <= hi.y(); ++j) {
      winding.crossings(j * h, k * h, line);
      // Crossings beyond x, summed: walk x upwards, dropping crossings passed.
      int beyond = 0;
      for (const Crossing& c : line) beyond += c.sign;
      std::size_t next = 0;
      const std::size_t row = (static_cast<std::size_t>(k - lo.z()) * dim.y() + (j - lo.y())) * dim.x();
      for (openvdb::Int32 i = lo.x(); i <= hi.x(); ++i) {
        const double x = i * h;
        while (next < line.size() && line[next].x <= x) beyond -= line[next++].sign;
        const bool inside = beyond >= 1;
        const float squared = d2[row + (i - lo.x())];
        const openvdb::Coord ijk(i, j, k);
        if (squared < far) {
          const float distance = std::sqrt(squared);
          accessor.setValueOn(ijk, inside ? -distance : distance);
        } else if (inside) {
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
