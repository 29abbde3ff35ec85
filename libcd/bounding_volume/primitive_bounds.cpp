#include "libcd/bounding_volume/primitive_bounds.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <cassert>

namespace snag {

PrimitiveBounds compute_primitive_bounds(const Scene& scene, const std::vector<Vec3>& x_t0,
                                         const std::vector<Vec3>& x_t1, double thickness) {
  PrimitiveBounds out;
  compute_primitive_bounds(scene, x_t0, x_t1, thickness, out);
  return out;
}

void compute_primitive_bounds(const Scene& scene, const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                              double thickness, PrimitiveBounds& out) {
  assert(x_t0.size() == scene.vertex_count() && x_t1.size() == scene.vertex_count());
  const auto& tris = scene.triangles();
  const auto& edges = scene.edges();
  out.triangles.resize(tris.size());
  out.triangle_radii.resize(tris.size());
  out.edges.resize(edges.size());
  out.vertices.resize(x_t0.size());

  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tris.size(), 1024), [&](const auto& r) {
    for (std::size_t f = r.begin(); f != r.end(); ++f) {
      const Vec3 c_t0[3] = {x_t0[tris[f][0]], x_t0[tris[f][1]], x_t0[tris[f][2]]};
      const Vec3 c_t1[3] = {x_t1[tris[f][0]], x_t1[tris[f][1]], x_t1[tris[f][2]]};
      out.triangles[f] = swept_dop(c_t0, c_t1, 3, thickness);
      const Vec3 points[6] = {c_t0[0], c_t0[1], c_t0[2], c_t1[0], c_t1[1], c_t1[2]};
      out.triangle_radii[f] = sphere_of_points(points, 6).radius + thickness;
    }
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, edges.size(), 1024), [&](const auto& r) {
    for (std::size_t e = r.begin(); e != r.end(); ++e) {
      const Vec3 c_t0[2] = {x_t0[edges[e][0]], x_t0[edges[e][1]]};
      const Vec3 c_t1[2] = {x_t1[edges[e][0]], x_t1[edges[e][1]]};
      out.edges[e] = swept_dop(c_t0, c_t1, 2, thickness);
    }
  });
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, x_t0.size(), 1024), [&](const auto& r) {
    for (std::size_t v = r.begin(); v != r.end(); ++v) out.vertices[v] = swept_dop(&x_t0[v], &x_t1[v], 1, thickness);
  });

  struct Box {
    Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  };
  const Box box = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, x_t0.size(), 4096), Box{},
      [&](const auto& r, Box b) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
          b.lo = min(b.lo, min(x_t0[v], x_t1[v]));
          b.hi = max(b.hi, max(x_t0[v], x_t1[v]));
        }
        return b;
      },
      [](Box a, const Box& b) {
        a.lo = min(a.lo, b.lo);
        a.hi = max(a.hi, b.hi);
        return a;
      });
  if (x_t0.empty()) {
    out.scene_lo = out.scene_hi = Vec3{};
  } else {
    const Vec3 corners[2] = {box.lo, box.hi};
    const double w = thickness + rounding_pad(corners, 2);
    out.scene_lo = box.lo - Vec3{w, w, w};
    out.scene_hi = box.hi + Vec3{w, w, w};
  }
}

}  // namespace snag
