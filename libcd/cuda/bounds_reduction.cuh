// Device-level entry point of the bounds stage, for the GPU pipeline that
// keeps its data on the device. The host entry point is in bounds_reduction.hpp.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>

#include "libcd/cuda/device_buffer.cuh"
#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag {

/// Results of the reductions, as left on the device.
struct DeviceBoundsSums {
  Vec3 lo, hi;                // box of all positions at t0 and t1
  double static_radius_sum;   // Σ static radii
  double swept_radius_sum;    // Σ swept radii
};

/// Runs the radii kernel and the reductions in stream order; nothing is synchronised.
/// @param positions      2·#V device positions: #V at t0 followed by #V at t1
/// @param vertex_count   #V (> 0)
/// @param triangles      #F device triangles (global vertex ids < #V)
/// @param static_radii, swept_radii  [out] #F device radii
/// @param sums           [out] one DeviceBoundsSums on the device
/// @param temp_storage   scratch for the reductions, grown as needed
/// Throws CudaError.
void triangle_bounds_on_device(const Vec3* positions, std::size_t vertex_count, const Triangle* triangles,
                               std::size_t triangle_count, double* static_radii, double* swept_radii,
                               DeviceBoundsSums* sums, DeviceBuffer<unsigned char>& temp_storage,
                               cudaStream_t stream);

}  // namespace snag
