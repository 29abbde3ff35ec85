#include "volume/penetration.hpp"

#include <openvdb/tools/Interpolation.h>

#include <algorithm>
#include <cmath>

#include "volume/closed_level_set.hpp"
#include "volume/region_box.hpp"
#include "volume/winding_columns.hpp"

namespace snag::volume {

namespace {

constexpr int kMaxSplits = 64;  // sub-triangles a side, bounding the samples of one large face

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * std::sqrt(squared_norm(cross(b - a, c - a))); }

struct FaceInside {
  double area = 0, depth = 0;
  bool inside = false;       // some sample below zero
  bool near_side = false;    // a sample inside lies at the box's side
};

// Samples face (a, b, c) on an n x n split into sub-triangles.
template <typename Sampler>
FaceInside sample_face(const Vec3& a, const Vec3& b, const Vec3& c, const Sampler& sampler, double h,
                       const Box& inner) {
  const double longest = std::sqrt(std::max({squared_norm(b - a), squared_norm(c - b), squared_norm(a - c)}));
  const int n = std::clamp(static_cast<int>(std::ceil(longest / h)), 1, kMaxSplits);
  const double sub_area = triangle_area(a, b, c) / (n * n);
  FaceInside out;
  // Values at the lattice points (i, j), i + j <= n: point a + i/n (b - a) + j/n (c - a).
  std::vector<double> values((n + 1) * (n + 2) / 2);
  auto at = [n](int i, int j) { return static_cast<std::size_t>(j * (n + 1) - j * (j - 1) / 2 + i); };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i + j <= n; ++i) {
      const Vec3 p = a + (static_cast<double>(i) / n) * (b - a) + (static_cast<double>(j) / n) * (c - a);
      const double value = sampler.wsSample(openvdb::Vec3d(p.x, p.y, p.z));
      values[at(i, j)] = value;
      if (value < 0) {
        out.inside = true;
        out.depth = std::max(out.depth, -value);
        if (!contains(inner, Box{p, p})) out.near_side = true;
      }
    }
  }
  if (!out.inside) return out;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i + j < n; ++i) {
      out.area += area_below_zero(sub_area, values[at(i, j)], values[at(i + 1, j)], values[at(i, j + 1)]);
      if (i + j + 1 < n) {
        out.area += area_below_zero(sub_area, values[at(i + 1, j)], values[at(i + 1, j + 1)], values[at(i, j + 1)]);
      }
    }
  }
  return out;
}

}  // namespace

double area_below_zero(double area, double f0, double f1, double f2) {
  const int below = (f0 < 0) + (f1 < 0) + (f2 < 0);
  if (below == 0) return 0;
  if (below == 3) return area;
  // Rotate so that f0 is the corner alone on its side.
  if ((f1 < 0) != (f0 < 0) && (f1 < 0) != (f2 < 0)) std::swap(f0, f1);
  else if ((f2 < 0) != (f0 < 0) && (f2 < 0) != (f1 < 0)) std::swap(f0, f2);
  // The corner's own part is a similar triangle of side fractions f0/(f0-f1), f0/(f0-f2).
  const double corner = area * (f0 / (f0 - f1)) * (f0 / (f0 - f2));
  return f0 < 0 ? corner : area - corner;
}

Penetration penetration(const TriangleMesh& open, const VertexFaces& open_faces, const std::vector<std::size_t>& seeds,
                        const TriangleMesh& closed, const Box& region, double voxel_size) {
  Penetration result;
  const Box limit = grown(mesh_box(closed), 2 * voxel_size);
  // One pass on a box with a band `half_width` voxels deep; false when the
  // part reached the box's sides.
  auto measure_in_band = [&](const VoxelBox& voxels, float half_width) {
    const double h = voxels.voxel_size;
    const Box world = world_box(voxels);
    const WindingColumns winding(closed, world);
    result.level_set = closed_level_set(closed, winding, voxels, half_width);
    const openvdb::tools::GridSampler<openvdb::FloatGrid, openvdb::tools::BoxSampler> sampler(*result.level_set);
    const Box inner = grown(world, -h);

    result.depth = result.area = 0;
    bool whole = true;
    std::vector<char> seen(open.triangles.size(), 0);
    std::vector<std::size_t> queue;
    for (std::size_t f : seeds) {
      if (!seen[f]) queue.push_back(f);
      seen[f] = 1;
    }
    while (!queue.empty()) {
      const std::size_t f = queue.back();
      queue.pop_back();
      const Triangle& t = open.triangles[f];
      const FaceInside face = sample_face(open.vertices[t[0]], open.vertices[t[1]], open.vertices[t[2]], sampler, h, inner);
      if (!face.inside) continue;
      result.area += face.area;
      result.depth = std::max(result.depth, face.depth);
      if (face.near_side) whole = false;
      for (Index v : t) {
        for (std::size_t i = open_faces.start[v]; i < open_faces.start[v + 1]; ++i) {
          const std::size_t g = open_faces.faces[i];
          if (!seen[g]) {
            seen[g] = 1;
            queue.push_back(g);
          }
        }
      }
    }
    return whole;
  };
  // The band deepens until the deepest point lies within it (the distance is
  // exact only there), at most to the box's diagonal: the surface crosses the
  // region, so no point of the box is farther from it.
  auto measure = [&](const VoxelBox& voxels) {
    const double h = voxels.voxel_size;
    const Box world = world_box(voxels);
    const double deepest = std::sqrt(squared_norm(world.hi - world.lo)) / h + 2;
    for (float half_width = 6;; half_width *= 2) {
      const bool whole = measure_in_band(voxels, half_width);
      if (result.depth < (half_width - 1) * h || half_width >= deepest) return whole;
    }
  };
  result.voxel_size = grow_until_whole(region, limit, voxel_size, 2, measure);
  result.level_set->setName("level_set");
  return result;
}

}  // namespace snag::volume
