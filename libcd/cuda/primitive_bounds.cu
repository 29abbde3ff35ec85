// Bounding volumes of triangles, edges and vertices on the GPU: the CUDA twin
// of libcd/bounding_volume/primitive_bounds.cpp (same per-primitive functions).
// Klosowski et al., "Efficient collision detection using bounding volume
// hierarchies of k-DOPs", IEEE TVCG 1998. Reductions: CUB DeviceReduce.
#include "libcd/cuda/primitive_bounds.cuh"

#include <cub/device/device_reduce.cuh>
#include <thrust/iterator/transform_iterator.h>

#include <algorithm>

#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/launch.cuh"

namespace snag {
namespace {

using detail::blocks_for;
using detail::thread_item;

struct Vec3Min {
  SNAG_HD_INLINE Vec3 operator()(const Vec3& a, const Vec3& b) const { return min(a, b); }
};
struct Vec3Max {
  SNAG_HD_INLINE Vec3 operator()(const Vec3& a, const Vec3& b) const { return max(a, b); }
};
struct DoubleMax {
  SNAG_HD_INLINE double operator()(double a, double b) const { return a > b ? a : b; }
};
struct FixedPointAdd {
  SNAG_HD_INLINE FixedPointSum operator()(const FixedPointSum& a, const FixedPointSum& b) const { return a + b; }
};
struct Quantize {
  int shift;
  SNAG_HD_INLINE FixedPointSum operator()(double r) const { return quantize_radius(r, shift); }
};

__global__ void triangle_bounds_kernel(const Triangle* tris, std::size_t n, const Vec3* x_t0, const Vec3* x_t1,
                                       double thickness, Dop18* dops, FloatBox* boxes, double* radii) {
  const std::uint64_t f = thread_item();
  if (f >= n) return;
  const Triangle t = tris[f];
  const Vec3 c_t0[3] = {x_t0[t[0]], x_t0[t[1]], x_t0[t[2]]};
  const Vec3 c_t1[3] = {x_t1[t[0]], x_t1[t[1]], x_t1[t[2]]};
  const Dop18 dop = swept_dop(c_t0, c_t1, 3, thickness);
  dops[f] = dop;
  boxes[f] = float_box_of(dop);
  const Vec3 points[6] = {c_t0[0], c_t0[1], c_t0[2], c_t1[0], c_t1[1], c_t1[2]};
  radii[f] = sphere_of_points(points, 6).radius + thickness;
}

__global__ void edge_bounds_kernel(const Edge* edges, std::size_t n, const Vec3* x_t0, const Vec3* x_t1,
                                   double thickness, Dop18* dops, FloatBox* boxes) {
  const std::uint64_t e = thread_item();
  if (e >= n) return;
  const Edge g = edges[e];
  const Vec3 c_t0[2] = {x_t0[g[0]], x_t0[g[1]]};
  const Vec3 c_t1[2] = {x_t1[g[0]], x_t1[g[1]]};
  const Dop18 dop = swept_dop(c_t0, c_t1, 2, thickness);
  dops[e] = dop;
  boxes[e] = float_box_of(dop);
}

__global__ void vertex_bounds_kernel(std::size_t n, const Vec3* x_t0, const Vec3* x_t1, double thickness, Dop18* dops,
                                     FloatBox* boxes) {
  const std::uint64_t v = thread_item();
  if (v >= n) return;
  const Dop18 dop = swept_dop(&x_t0[v], &x_t1[v], 1, thickness);
  dops[v] = dop;
  boxes[v] = float_box_of(dop);
}

}  // namespace

void compute_primitive_bounds_on_device(const Triangle* triangles, std::size_t triangle_count, const Edge* edges,
                                        std::size_t edge_count, const Vec3* x_t0, const Vec3* x_t1,
                                        std::size_t vertex_count, double thickness, DevicePrimitiveBounds& out,
                                        cudaStream_t stream, Vec3& scene_lo, Vec3& scene_hi, double& max_radius,
                                        const GrowthCheck& check) {
  check_growth(check, out.triangles.growth_bytes(triangle_count) + out.triangle_boxes.growth_bytes(triangle_count) +
                          out.triangle_radii.growth_bytes(triangle_count) + out.edges.growth_bytes(edge_count) +
                          out.vertices.growth_bytes(vertex_count) + out.edge_boxes.growth_bytes(edge_count) +
                          out.vertex_boxes.growth_bytes(vertex_count) + out.box.growth_bytes(4) +
                          out.max_radius.growth_bytes(1));
  out.triangles.resize(triangle_count);
  out.triangle_boxes.resize(triangle_count);
  out.triangle_radii.resize(triangle_count);
  out.edges.resize(edge_count);
  out.vertices.resize(vertex_count);
  out.edge_boxes.resize(edge_count);
  out.vertex_boxes.resize(vertex_count);
  out.box.resize(4);
  out.max_radius.resize(1);
  if (triangle_count > 0) {
    triangle_bounds_kernel<<<blocks_for(triangle_count), detail::kBlockSize, 0, stream>>>(
        triangles, triangle_count, x_t0, x_t1, thickness, out.triangles.data(), out.triangle_boxes.data(),
        out.triangle_radii.data());
    SNAG_CUDA_CHECK_LAUNCH();
  }
  if (edge_count > 0) {
    edge_bounds_kernel<<<blocks_for(edge_count), detail::kBlockSize, 0, stream>>>(
        edges, edge_count, x_t0, x_t1, thickness, out.edges.data(), out.edge_boxes.data());
    SNAG_CUDA_CHECK_LAUNCH();
  }
  if (vertex_count > 0) {
    vertex_bounds_kernel<<<blocks_for(vertex_count), detail::kBlockSize, 0, stream>>>(
        vertex_count, x_t0, x_t1, thickness, out.vertices.data(), out.vertex_boxes.data());
    SNAG_CUDA_CHECK_LAUNCH();
  }

  const Vec3 lo_init{1e300, 1e300, 1e300}, hi_init{-1e300, -1e300, -1e300};
  const double radius_init = 0;  // radii are ≥ 0; the CPU takes the maximum of the same values
  std::size_t need = 0, bytes = 0;
  if (vertex_count > 0) {
    SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(nullptr, bytes, x_t0, out.box.data(), vertex_count, Vec3Min{}, lo_init,
                                              stream));
    need = std::max(need, bytes);
  }
  if (triangle_count > 0) {
    SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(nullptr, bytes, out.triangle_radii.data(), out.max_radius.data(),
                                              triangle_count, DoubleMax{}, radius_init, stream));
    need = std::max(need, bytes);
  }
  detail::ensure_scratch(out.temp, need);
  if (vertex_count > 0) {
    const Vec3* frames[2] = {x_t0, x_t1};
    for (int k = 0; k < 2; ++k) {
      bytes = out.temp.size();
      SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(out.temp.data(), bytes, frames[k], out.box.data() + 2 * k,
                                                vertex_count, Vec3Min{}, lo_init, stream));
      bytes = out.temp.size();
      SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(out.temp.data(), bytes, frames[k], out.box.data() + 2 * k + 1,
                                                vertex_count, Vec3Max{}, hi_init, stream));
    }
  }
  if (triangle_count > 0) {
    bytes = out.temp.size();
    SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(out.temp.data(), bytes, out.triangle_radii.data(),
                                              out.max_radius.data(), triangle_count, DoubleMax{}, radius_init,
                                              stream));
  }
  Vec3 box[4];
  max_radius = 0;
  ReadBack read(stream);
  if (vertex_count > 0) read.add(box, out.box.data(), 4);
  if (triangle_count > 0) read.add(&max_radius, out.max_radius.data());
  read.wait();
  if (vertex_count == 0) {
    scene_lo = scene_hi = Vec3{};
    return;
  }
  // As compute_primitive_bounds: the box of both frames, widened by thickness and pad.
  const Vec3 lo = min(box[0], box[2]), hi = max(box[1], box[3]);
  const Vec3 corners[2] = {lo, hi};
  const double w = thickness + rounding_pad(corners, 2);
  scene_lo = lo - Vec3{w, w, w};
  scene_hi = hi + Vec3{w, w, w};
}

FixedPointSum radius_sum_on_device(DevicePrimitiveBounds& bounds, std::size_t triangle_count, int shift,
                                   cudaStream_t stream) {
  FixedPointSum sum;
  if (triangle_count == 0) return sum;
  bounds.radius_sum.resize(1);
  const auto quantized = thrust::make_transform_iterator(bounds.triangle_radii.data(), Quantize{shift});
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(nullptr, bytes, quantized, bounds.radius_sum.data(), triangle_count,
                                            FixedPointAdd{}, FixedPointSum{}, stream));
  detail::ensure_scratch(bounds.temp, bytes);
  bytes = bounds.temp.size();
  SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(bounds.temp.data(), bytes, quantized, bounds.radius_sum.data(),
                                            triangle_count, FixedPointAdd{}, FixedPointSum{}, stream));
  bounds.radius_sum.download(&sum, 1);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));
  return sum;
}

}  // namespace snag
