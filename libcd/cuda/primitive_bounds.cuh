// The bounding-volume stage on the GPU, mirroring
// libcd/bounding_volume/primitive_bounds.cpp: swept 18-DOPs of triangles,
// edges and vertices and triangle sphere radii, one thread per primitive, with
// the same SNAG_HD functions (so the same rounding pad and bits); the scene
// box and the radii's maximum and exact fixed-point sum by CUB reductions
// (min, max and integer addition do not depend on the reduction order).
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>

#include "libcd/bounding_volume/dop18.hpp"
#include "libcd/bounding_volume/float_box.hpp"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/geometry/vec3.hpp"
#include "libcd/grid/radius_sum.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag {

/// Device arrays of the bounds of one step (global ids, as PrimitiveBounds).
struct DevicePrimitiveBounds {
  DeviceBuffer<Dop18> triangles;          ///< #F
  DeviceBuffer<FloatBox> triangle_boxes;  ///< #F, float_box_of(triangles[f]): the pair tests' first test
  DeviceBuffer<Dop18> edges;              ///< #E
  DeviceBuffer<Dop18> vertices;           ///< #V
  DeviceBuffer<FloatBox> edge_boxes;      ///< #E, float_box_of(edges[e]): the feature culling's first test
  DeviceBuffer<FloatBox> vertex_boxes;    ///< #V, float_box_of(vertices[v])
  DeviceBuffer<double> triangle_radii;    ///< #F, thickness included
  DeviceBuffer<Vec3> box;                 ///< 4: lo/hi of x_t0, lo/hi of x_t1 (reduction results)
  DeviceBuffer<double> max_radius;        ///< 1
  DeviceBuffer<FixedPointSum> radius_sum; ///< 1
  DeviceBuffer<unsigned char> temp;       ///< CUB scratch

  explicit DevicePrimitiveBounds(cudaStream_t stream)
      : triangles(0, stream),
        triangle_boxes(0, stream),
        edges(0, stream),
        vertices(0, stream),
        edge_boxes(0, stream),
        vertex_boxes(0, stream),
        triangle_radii(0, stream),
        box(0, stream),
        max_radius(0, stream),
        radius_sum(0, stream),
        temp(0, stream) {}
};

/// Computes the DOPs and radii of all primitives, their float boxes,
/// the scene box (inflated by thickness and rounding pad exactly as
/// compute_primitive_bounds) and the largest radius. Waits for the stream
/// (the box and maximum come to the host).
/// @param triangles  #F device triangles; edges #E device edges
/// @param x_t0, x_t1 #V device positions (the same pointer twice for static detection)
/// @param thickness  ≥ 0, scene units
/// @param[out] scene_lo, scene_hi, max_radius  host values
/// @param check  told what the bounds' arrays add before they allocate (it may throw)
/// Throws CudaError, or what `check` throws.
void compute_primitive_bounds_on_device(const Triangle* triangles, std::size_t triangle_count, const Edge* edges,
                                        std::size_t edge_count, const Vec3* x_t0, const Vec3* x_t1,
                                        std::size_t vertex_count, double thickness, DevicePrimitiveBounds& out,
                                        cudaStream_t stream, Vec3& scene_lo, Vec3& scene_hi, double& max_radius,
                                        const GrowthCheck& check = {});

/// The exact sum of the quantized triangle radii (radius_sum.hpp) for the
/// given shift, by a device reduction; waits for the stream. Throws CudaError.
FixedPointSum radius_sum_on_device(DevicePrimitiveBounds& bounds, std::size_t triangle_count, int shift,
                                   cudaStream_t stream);

}  // namespace snag
