// Bounding volumes of triangles, edges and vertices on the GPU: the CUDA twin
// of libcd/bounding_volume/primitive_bounds.cpp (same per-primitive functions).
// Klosowski et al., "Efficient collision detection using bounding volume
// hierarchies of k-DOPs", IEEE TVCG 1998.
//
// The scene box, the largest radius and the radii's exact sum are reduced
// inside the kernels that compute the primitives' bounds (a block's values,
// then one atomic per block and value), with one read-back: each a minimum,
// maximum or integer sum, which no order changes. A double is reduced as its
// order key (order_key.hpp; a minimum as the maximum of the keys'
// complements), so that 64-bit integer atomics take it.
#include "libcd/cuda/primitive_bounds.cuh"

#include <algorithm>

#include "libcd/bounding_volume/primitive_bounds.hpp"
#include "libcd/cuda/launch.cuh"
#include "libcd/geometry/order_key.hpp"

namespace snag {
namespace {

using detail::blocks_for;
using detail::thread_item;

/// Maximizes *to over the block's `count` keys per thread: each warp's
/// maximum by shuffles, then the block's in shared memory, then one atomic
/// per key. Every thread of the block calls it.
template <int count>
__device__ void block_max_to(const std::uint64_t (&keys)[count], std::uint64_t* to) {
  __shared__ unsigned long long block[count];
  if (threadIdx.x < count) block[threadIdx.x] = 0;
  __syncthreads();
  for (int k = 0; k < count; ++k) {
    unsigned long long key = keys[k];
    for (int offset = 16; offset > 0; offset /= 2) key = ::max(key, __shfl_xor_sync(0xffffffffu, key, offset));
    if ((threadIdx.x & 31u) == 0) atomicMax(&block[k], key);
  }
  __syncthreads();
  if (threadIdx.x < count && block[threadIdx.x] != 0)
    atomicMax(reinterpret_cast<unsigned long long*>(to + threadIdx.x), block[threadIdx.x]);
}

/// A block's DOPs, written a warp in one piece (144 bytes a thread, stored
/// by itself, lay 144 bytes apart from its neighbours').
using DopStage = detail::WarpRunStage<Dop18, detail::kBlockSize>;

__global__ void triangle_bounds_kernel(const Triangle* tris, std::size_t n, const Vec3* x_t0, const Vec3* x_t1,
                                       double thickness, Dop18* dops, FloatBox* boxes, double* radii,
                                       BoundsReduction* reduced) {
  __shared__ DopStage stage;
  const std::uint64_t f = thread_item();
  std::uint64_t key[1] = {0};
  Dop18 dop;
  if (f < n) {
    const Triangle t = tris[f];
    const Vec3 c_t0[3] = {x_t0[t[0]], x_t0[t[1]], x_t0[t[2]]};
    const Vec3 c_t1[3] = {x_t1[t[0]], x_t1[t[1]], x_t1[t[2]]};
    dop = swept_dop(c_t0, c_t1, 3, thickness);
    boxes[f] = float_box_of(dop);
    const Vec3 points[6] = {c_t0[0], c_t0[1], c_t0[2], c_t1[0], c_t1[1], c_t1[2]};
    const double radius = sphere_of_points(points, 6).radius + thickness;
    radii[f] = radius;
    key[0] = order_key(radius);
  }
  stage.write(dop, f, n, dops);
  block_max_to(key, &reduced->max_radius);
}

__global__ void edge_bounds_kernel(const Edge* edges, std::size_t n, const Vec3* x_t0, const Vec3* x_t1,
                                   double thickness, Dop18* dops, FloatBox* boxes) {
  __shared__ DopStage stage;
  const std::uint64_t e = thread_item();
  Dop18 dop;
  if (e < n) {
    const Edge g = edges[e];
    const Vec3 c_t0[2] = {x_t0[g[0]], x_t0[g[1]]};
    const Vec3 c_t1[2] = {x_t1[g[0]], x_t1[g[1]]};
    dop = swept_dop(c_t0, c_t1, 2, thickness);
    boxes[e] = float_box_of(dop);
  }
  stage.write(dop, e, n, dops);
}

/// The vertices' swept DOPs and their float boxes (none when `dops` is null),
/// and the scene box over both frames' positions.
__global__ void vertex_bounds_kernel(std::size_t n, const Vec3* x_t0, const Vec3* x_t1, double thickness, Dop18* dops,
                                     FloatBox* boxes, BoundsReduction* reduced) {
  __shared__ DopStage stage;
  const std::uint64_t v = thread_item();
  std::uint64_t keys[12] = {};
  if (dops != nullptr) {  // the same for every thread
    Dop18 dop;
    if (v < n) {
      dop = swept_dop(&x_t0[v], &x_t1[v], 1, thickness);
      boxes[v] = float_box_of(dop);
    }
    stage.write(dop, v, n, dops);
  }
  if (v < n) {
    const Vec3 frames[2] = {x_t0[v], x_t1[v]};
    for (int k = 0; k < 2; ++k) {
      const double p[3] = {frames[k].x, frames[k].y, frames[k].z};
      for (int a = 0; a < 3; ++a) {
        keys[6 * k + a] = ~order_key(p[a]);
        keys[6 * k + 3 + a] = order_key(p[a]);
      }
    }
  }
  block_max_to(keys, reduced->box);
}

/// The radii's exact fixed-point sum (radius_sum.hpp), with the shift of the
/// largest radius that triangle_bounds_kernel left: a block's sum, then the
/// low word added with one atomic and its carry and the high word with two more.
__global__ void radius_sum_kernel(const double* radii, std::size_t n, BoundsReduction* reduced) {
  const int shift = radius_sum_shift(::max(0.0, from_order_key(reduced->max_radius)));
  const std::uint64_t f = thread_item();
  FixedPointSum sum;
  if (f < n) sum = quantize_radius(radii[f], shift);
  __shared__ FixedPointSum warps[detail::kBlockSize / 32];
  for (int offset = 16; offset > 0; offset /= 2) {
    FixedPointSum other;
    other.lo = __shfl_xor_sync(0xffffffffu, sum.lo, offset);
    other.hi = __shfl_xor_sync(0xffffffffu, sum.hi, offset);
    sum = sum + other;
  }
  if ((threadIdx.x & 31u) == 0) warps[threadIdx.x / 32] = sum;
  __syncthreads();
  if (threadIdx.x != 0) return;
  FixedPointSum block;
  for (unsigned w = 0; w < blockDim.x / 32; ++w) block = block + warps[w];
  auto* lo = reinterpret_cast<unsigned long long*>(&reduced->radius_sum.lo);
  auto* hi = reinterpret_cast<unsigned long long*>(&reduced->radius_sum.hi);
  const unsigned long long before = atomicAdd(lo, static_cast<unsigned long long>(block.lo));
  const unsigned long long carry = before + block.lo < before ? 1 : 0;
  if (block.hi + carry != 0) atomicAdd(hi, static_cast<unsigned long long>(block.hi + carry));
}

}  // namespace

void compute_primitive_bounds_on_device(const Triangle* triangles, std::size_t triangle_count, const Edge* edges,
                                        std::size_t edge_count, const Vec3* x_t0, const Vec3* x_t1,
                                        std::size_t vertex_count, double thickness, bool with_radius_sum,
                                        bool with_features, DevicePrimitiveBounds& out, cudaStream_t stream,
                                        BoundsSummary& summary, const GrowthCheck& check) {
  // The edges' and vertices' bounds only for the feature stage.
  const std::size_t feature_edges = with_features ? edge_count : 0, feature_vertices = with_features ? vertex_count : 0;
  check_growth(check, out.triangles.growth_bytes(triangle_count) + out.triangle_boxes.growth_bytes(triangle_count) +
                          out.triangle_radii.growth_bytes(triangle_count) + out.edges.growth_bytes(feature_edges) +
                          out.vertices.growth_bytes(feature_vertices) + out.edge_boxes.growth_bytes(feature_edges) +
                          out.vertex_boxes.growth_bytes(feature_vertices) + out.reduced.growth_bytes(1));
  out.triangles.resize(triangle_count);
  out.triangle_boxes.resize(triangle_count);
  out.triangle_radii.resize(triangle_count);
  out.edges.resize(feature_edges);
  out.vertices.resize(feature_vertices);
  out.edge_boxes.resize(feature_edges);
  out.vertex_boxes.resize(feature_vertices);
  out.reduced.resize(1);
  BoundsReduction* reduced = out.reduced.data();
  SNAG_CUDA_CHECK(cudaMemsetAsync(reduced, 0, sizeof(BoundsReduction), stream));
  if (triangle_count > 0) {
    triangle_bounds_kernel<<<blocks_for(triangle_count), detail::kBlockSize, 0, stream>>>(
        triangles, triangle_count, x_t0, x_t1, thickness, out.triangles.data(), out.triangle_boxes.data(),
        out.triangle_radii.data(), reduced);
    SNAG_CUDA_CHECK_LAUNCH();
    if (with_radius_sum) {
      radius_sum_kernel<<<blocks_for(triangle_count), detail::kBlockSize, 0, stream>>>(out.triangle_radii.data(),
                                                                                       triangle_count, reduced);
      SNAG_CUDA_CHECK_LAUNCH();
    }
  }
  if (feature_edges > 0) {
    edge_bounds_kernel<<<blocks_for(edge_count), detail::kBlockSize, 0, stream>>>(
        edges, edge_count, x_t0, x_t1, thickness, out.edges.data(), out.edge_boxes.data());
    SNAG_CUDA_CHECK_LAUNCH();
  }
  if (vertex_count > 0) {  // the scene box, with or without the vertices' bounds
    vertex_bounds_kernel<<<blocks_for(vertex_count), detail::kBlockSize, 0, stream>>>(
        vertex_count, x_t0, x_t1, thickness, with_features ? out.vertices.data() : nullptr,
        with_features ? out.vertex_boxes.data() : nullptr, reduced);
    SNAG_CUDA_CHECK_LAUNCH();
  }
  BoundsReduction host;
  ReadBack(stream).add(&host, reduced).wait();

  // As the CPU's reductions, from the same starts: radii from 0 (they are
  // not negative), the box from ±1e300.
  summary = BoundsSummary{};
  if (triangle_count > 0) {
    summary.max_radius = std::max(0.0, from_order_key(host.max_radius));
    if (with_radius_sum) {
      summary.radius_shift = radius_sum_shift(summary.max_radius);
      summary.radius_sum = host.radius_sum;
    }
  }
  if (vertex_count == 0) return;
  double box[12];
  for (int k = 0; k < 12; ++k) box[k] = from_order_key(k % 6 < 3 ? ~host.box[k] : host.box[k]);
  const Vec3 lo_init{1e300, 1e300, 1e300}, hi_init{-1e300, -1e300, -1e300};
  const Vec3 lo_t0{box[0], box[1], box[2]}, hi_t0{box[3], box[4], box[5]};
  const Vec3 lo_t1{box[6], box[7], box[8]}, hi_t1{box[9], box[10], box[11]};
  // As compute_primitive_bounds: the box of both frames, widened by thickness and pad.
  const Vec3 lo = min(min(lo_init, lo_t0), min(lo_init, lo_t1)), hi = max(max(hi_init, hi_t0), max(hi_init, hi_t1));
  const Vec3 corners[2] = {lo, hi};
  const double w = thickness + rounding_pad(corners, 2);
  summary.scene_lo = lo - Vec3{w, w, w};
  summary.scene_hi = hi + Vec3{w, w, w};
}

}  // namespace snag
