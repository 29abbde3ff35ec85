#include "libcd/stats/cache_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "libcd/bounding_volume/bounding_sphere.hpp"
#include "libcd/grid/cell_size.hpp"
#include "libcd/narrow_phase/triangle_triangle.hpp"

namespace snag {

namespace {

// The broad phase's static triangle sphere (bounding_volume/bounding_sphere.hpp).
double sphere_radius(Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 corners[3] = {a, b, c};
  return sphere_of_points(corners, 3).radius;
}

// Loop subdivision makes four half-size copies of a triangle (the middle one
// turned by 180 degrees), whose box-centred spheres have half the radius; so a
// radius r needs the smallest k with r / 2^k <= limit.
int levels_needed(double radius, double limit) {
  int levels = 0;
  while (radius > limit && levels < 64) {
    radius *= 0.5;
    ++levels;
  }
  return levels;
}

bool is_degenerate(const Triangle& t, const std::vector<Vec3>& x) {
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return true;
  return is_degenerate_triangle(x[t[0]], x[t[1]], x[t[2]]);
}

}  // namespace

CacheStatistics compute_cache_statistics(const FrameSource& source, double lambda) {
  const Scene& scene = source.scene();
  CacheStatistics stats;
  stats.lambda = lambda;
  stats.frames = source.frame_count();
  for (const Object& object : scene.objects()) {
    ObjectStatistics o;
    o.name = object.name;
    o.vertices = object.vertex_count;
    o.triangles = object.triangles.size();
    o.edges = object.edges.size();
    EdgeCounts kinds = count_edge_kinds(object);
    o.boundary_edges = kinds.boundary;
    o.non_manifold_edges = kinds.non_manifold;
    stats.objects.push_back(o);
  }
  if (stats.frames == 0) return stats;
  stats.first_time = source.frame_time(0);
  stats.last_time = source.frame_time(stats.frames - 1);

  const double inf = std::numeric_limits<double>::infinity();
  stats.bounds_min = {inf, inf, inf};
  stats.bounds_max = {-inf, -inf, -inf};
  stats.sphere_radius = {inf, 0, 0};
  stats.cell_size = {inf, 0, 0};
  double radius_sum = 0;
  std::size_t radius_count = 0;

  std::vector<Vec3> previous, current;
  double previous_cell = 0;
  const auto& triangles = scene.triangles();
  for (std::size_t f = 0; f < stats.frames; ++f) {
    source.read_frame(f, current);
    for (const Vec3& p : current) {
      stats.bounds_min = min(stats.bounds_min, p);
      stats.bounds_max = max(stats.bounds_max, p);
    }
    if (f == 0) {
      for (std::size_t o = 0; o < scene.objects().size(); ++o) {
        for (Index t = scene.triangle_offset(o); t < scene.triangle_offset(o + 1); ++t) {
          stats.objects[o].degenerate_triangles += is_degenerate(triangles[t], current);
        }
      }
    }
    std::vector<double> radii(triangles.size());
    double frame_sum = 0;
    for (std::size_t t = 0; t < triangles.size(); ++t) {
      const Triangle& tri = triangles[t];
      radii[t] = sphere_radius(current[tri[0]], current[tri[1]], current[tri[2]]);
      frame_sum += radii[t];
      stats.sphere_radius.min = std::min(stats.sphere_radius.min, radii[t]);
      stats.sphere_radius.max = std::max(stats.sphere_radius.max, radii[t]);
    }
    radius_sum += frame_sum;
    radius_count += triangles.size();
    const double cell = virtual_subdivision_cell_size(radii, lambda);
    stats.cell_size.min = std::min(stats.cell_size.min, cell);
    stats.cell_size.max = std::max(stats.cell_size.max, cell);
    stats.cell_size.mean += cell / static_cast<double>(stats.frames);

    std::size_t subdivided = 0;
    for (double r : radii) {
      int levels = levels_needed(r, cell / 3.0);
      subdivided += levels > 0;
      stats.subdivision_levels = std::max(stats.subdivision_levels, levels);
    }
    stats.subdivided_triangles = std::max(stats.subdivided_triangles, subdivided);

    if (f > 0 && previous_cell > 0) {
      for (std::size_t v = 0; v < current.size(); ++v) {
        double d = std::sqrt(squared_norm(current[v] - previous[v])) / previous_cell;
        if (d > stats.max_displacement_over_cell) {
          stats.max_displacement_over_cell = d;
          stats.max_displacement_frame = f - 1;
          stats.max_displacement_vertex = v;
        }
      }
    }
    previous_cell = cell;
    std::swap(previous, current);
  }
  if (radius_count == 0) stats.sphere_radius = {0, 0, 0};
  else stats.sphere_radius.mean = radius_sum / static_cast<double>(radius_count);
  return stats;
}

}  // namespace snag
