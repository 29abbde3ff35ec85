#include "volume/region_measure.hpp"

#include <algorithm>
#include <cmath>

#include "volume/intersection_curve.hpp"
#include "volume/overlap_volume.hpp"
#include "volume/penetration.hpp"
#include "volume/self_overlap_volume.hpp"

namespace snag::volume {

namespace {

std::string describe(const ObjectShape& shape) {
  if (shape.closed()) return shape.name + " is closed";
  std::string text = shape.name + " is open (" + std::to_string(shape.edges.boundary) + " boundary edges";
  if (shape.edges.non_manifold > 0) text += ", " + std::to_string(shape.edges.non_manifold) + " non-manifold edges";
  return text + ")";
}

Box region_box(const report::RegionRecord& region) { return {region.bounds.lo, region.bounds.hi}; }

std::string region_grid(const report::RegionRecord& region, const char* what) {
  return "region_" + std::to_string(region.id) + "_" + what;
}

}  // namespace

ObjectShape object_shape(const Object& object) { return {object.name, count_edge_kinds(object)}; }

std::vector<std::size_t> faces_near(const TriangleMesh& mesh, const Box& bounds) {
  std::vector<std::size_t> faces;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (overlaps(triangle_box(mesh, t), bounds)) faces.push_back(t);
  }
  return faces;
}

double region_voxel_size(const RegionSide& a, const RegionSide& b, bool self, const Box& bounds) {
  double sum = 0;
  std::size_t edges = 0;
  for (const RegionSide* side : {&a, &b}) {
    if (self && side == &b) break;
    for (std::size_t f : side->faces) {
      const Triangle& t = side->mesh->triangles[f];
      for (int e = 0; e < 3; ++e) {
        sum += std::sqrt(squared_norm(side->mesh->vertices[t[(e + 1) % 3]] - side->mesh->vertices[t[e]]));
        ++edges;
      }
    }
  }
  const double side = longest_side(bounds);
  const double from_box = side / 16;
  if (edges > 0 && sum > 0) {
    const double from_faces = 0.5 * sum / static_cast<double>(edges);
    return from_box > 0 ? std::min(from_faces, from_box) : from_faces;
  }
  return from_box > 0 ? from_box : 1e-3;
}

MeasuredRegion measure_region(const report::RegionRecord& region, const RegionSide& a, const RegionSide& b,
                              double voxel_size) {
  const bool self = region.object_a == region.object_b;
  const Box bounds = region_box(region);
  const double h = voxel_size > 0 ? voxel_size : region_voxel_size(a, b, self, bounds);
  MeasuredRegion out;
  report::RegionMeasures& m = out.measures;
  m.reason = self ? describe(a.shape) : describe(a.shape) + ", " + describe(b.shape);

  if (self && a.shape.closed()) {
    m.measure = "self_overlap_volume";
    const SelfOverlapVolume fine = self_overlap_volume(*a.mesh, bounds, h);
    const SelfOverlapVolume coarse = self_overlap_volume(*a.mesh, bounds, 2 * fine.voxel_size);
    m.voxel_size = fine.voxel_size;
    m.volume = fine.volume;
    m.volume_error = std::abs(fine.volume - coarse.volume);
    out.grids.push_back({region_grid(region, "self_overlap"), fine.overlap});
  } else if (!self && a.shape.closed() && b.shape.closed()) {
    m.measure = "overlap_volume";
    const OverlapVolume fine = overlap_volume(*a.mesh, *b.mesh, bounds, h);
    const OverlapVolume coarse = overlap_volume(*a.mesh, *b.mesh, bounds, 2 * fine.voxel_size);
    m.voxel_size = fine.voxel_size;
    m.volume = fine.volume;
    m.volume_error = std::abs(fine.volume - coarse.volume);
    if (fine.overlap) {
      out.grids.push_back({a.shape.name, fine.level_set_a});
      out.grids.push_back({b.shape.name, fine.level_set_b});
      out.grids.push_back({region_grid(region, "overlap"), fine.overlap});
    }
  } else if (!self && a.shape.closed() != b.shape.closed()) {
    m.measure = "penetration";
    const RegionSide& open = a.shape.closed() ? b : a;
    const RegionSide& closed = a.shape.closed() ? a : b;
    const Penetration fine = penetration(*open.mesh, *open.vertex_faces, open.faces, *closed.mesh, bounds, h);
    const Penetration coarse =
        penetration(*open.mesh, *open.vertex_faces, open.faces, *closed.mesh, bounds, 2 * fine.voxel_size);
    m.voxel_size = fine.voxel_size;
    m.depth = fine.depth;
    m.depth_error = std::abs(fine.depth - coarse.depth);
    m.area = fine.area;
    m.area_error = std::abs(fine.area - coarse.area);
    out.grids.push_back({closed.shape.name, fine.level_set});
  } else {
    m.measure = "curve_length";
    const CurveLength curve = intersection_curve_length(*a.mesh, a.faces, *b.mesh, b.faces, self);
    m.curve_length = curve.length;
    m.segments = curve.segments;
  }
  return out;
}

}  // namespace snag::volume
