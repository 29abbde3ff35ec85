// The bounding-volume stage on the GPU, mirroring
// libcd/bounding_volume/primitive_bounds.cpp: swept 18-DOPs of triangles,
// edges and vertices and triangle sphere radii, one thread per primitive, with
// the same SNAG_HD functions (so the same rounding pad and bits); the scene
// box and the radii's maximum and exact fixed-point sum reduced by the same
// kernels (min, max and integer addition do not depend on the order).
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>

#include "libcd/bounding_volume/dop18.hpp"
#include "libcd/bounding_volume/float_box.hpp"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/geometry/vec3.hpp"
#include "libcd/grid/radius_sum.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag {

/// bounds[i] read in 8-byte words (a FloatBox is 8-byte aligned) through the
/// read-only cache: three loads where a member-by-member copy takes six.
__device__ __forceinline__ FloatBox read_box(const FloatBox* bounds, Index i) {
  const auto* words = reinterpret_cast<const float2*>(bounds + i);
  const float2 a = __ldg(words), b = __ldg(words + 1), c = __ldg(words + 2);
  return {{a.x, a.y, b.x}, {b.y, c.x, c.y}};
}

/// bounds[i] read in 16-byte words through the read-only cache: nine loads
/// where a member-by-member copy takes eighteen. Arrays of DOPs come from
/// the device allocator (256-byte aligned) and a DOP is 144 bytes, so every
/// element starts on a 16-byte boundary.
__device__ __forceinline__ Dop18 read_dop(const Dop18* bounds, Index i) {
  static_assert(sizeof(Dop18) == 2 * kDopAxes * sizeof(double) && sizeof(Dop18) % 16 == 0,
                "a DOP is nine 16-byte words: lo, then hi");
  const auto* words = reinterpret_cast<const double2*>(bounds + i);
  Dop18 dop;
#pragma unroll
  for (int k = 0; k < kDopAxes; ++k) {
    const double2 w = __ldg(words + k);
    const int j = 2 * k;  // the words' doubles j and j + 1 of lo[0..8], hi[0..8]
    (j < kDopAxes ? dop.lo[j] : dop.hi[j - kDopAxes]) = w.x;
    (j + 1 < kDopAxes ? dop.lo[j + 1] : dop.hi[j + 1 - kDopAxes]) = w.y;
  }
  return dop;
}

/// The bounds kernels' reductions as they leave them on the device (zeroed
/// before they run), each value an order key (primitive_bounds.cu): an
/// integer that orders as the double does, maximized by atomics.
struct BoundsReduction {
  std::uint64_t box[12];     ///< lo (the keys' complements) then hi of x_t0, the same of x_t1; x, y, z each
  std::uint64_t max_radius;  ///< the largest triangle radius
  FixedPointSum radius_sum;  ///< the quantized radii's sum, with the shift of the largest (radius_sum.hpp)
};

/// What the bounds stage brings to the host.
struct BoundsSummary {
  Vec3 scene_lo, scene_hi;   ///< both frames' box, widened as compute_primitive_bounds widens it
  double max_radius = 0;     ///< the largest triangle radius (0 without triangles)
  FixedPointSum radius_sum;  ///< the radii's exact sum (when asked for)
  int radius_shift = 0;      ///< its shift: radius_sum_shift(max_radius)
};

/// Device arrays of the bounds of one step (global ids, as PrimitiveBounds).
struct DevicePrimitiveBounds {
  DeviceBuffer<Dop18> triangles;          ///< #F
  DeviceBuffer<FloatBox> triangle_boxes;  ///< #F, float_box_of(triangles[f]): the pair tests' first test
  DeviceBuffer<Dop18> edges;              ///< #E
  DeviceBuffer<Dop18> vertices;           ///< #V
  DeviceBuffer<FloatBox> edge_boxes;      ///< #E, float_box_of(edges[e]): the feature culling's first test
  DeviceBuffer<FloatBox> vertex_boxes;    ///< #V, float_box_of(vertices[v])
  DeviceBuffer<double> triangle_radii;    ///< #F, thickness included
  DeviceBuffer<BoundsReduction> reduced;  ///< 1: the box, the largest radius and the radii's sum

  explicit DevicePrimitiveBounds(cudaStream_t stream)
      : triangles(0, stream),
        triangle_boxes(0, stream),
        edges(0, stream),
        vertices(0, stream),
        edge_boxes(0, stream),
        vertex_boxes(0, stream),
        triangle_radii(0, stream),
        reduced(0, stream) {}
};

/// Computes the DOPs and radii of the triangles and, with with_features, of
/// the edges and vertices (the feature stage's), their float boxes, the
/// scene box (inflated by thickness and rounding pad exactly as
/// compute_primitive_bounds), the largest radius and, with with_radius_sum,
/// the exact sum of the radii (radius_sum.hpp, as the CPU's cell size takes
/// it). Waits for the stream once (the summary comes to the host).
/// @param triangles  #F device triangles; edges #E device edges
/// @param x_t0, x_t1 #V device positions (the same pointer twice for static detection)
/// @param thickness  ≥ 0, scene units
/// @param[out] summary  host values
/// @param check  told what the bounds' arrays add before they allocate (it may throw)
/// Throws CudaError, or what `check` throws.
void compute_primitive_bounds_on_device(const Triangle* triangles, std::size_t triangle_count, const Edge* edges,
                                        std::size_t edge_count, const Vec3* x_t0, const Vec3* x_t1,
                                        std::size_t vertex_count, double thickness, bool with_radius_sum,
                                        bool with_features, DevicePrimitiveBounds& out, cudaStream_t stream,
                                        BoundsSummary& summary, const GrowthCheck& check = {});

}  // namespace snag
