// Triangle bounding spheres, scene box and mean radius on the GPU.
// Paper: Wong, Leach and Zambetta, "Virtual subdivision for GPU based collision
// detection of deformable objects using a uniform grid" (cell size, eq. 5.1).
// Reductions: CUB DeviceReduce (Merrill and Garland, single-pass reductions).
#include "libcd/cuda/bounds_reduction.cuh"
#include "libcd/cuda/bounds_reduction.hpp"

#include <cub/device/device_reduce.cuh>

#include <algorithm>
#include <cassert>
#include <limits>

#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/cuda_event.cuh"
#include "libcd/cuda/triangle_sphere.hpp"

namespace snag {
namespace {

static_assert(sizeof(Triangle) == 3 * sizeof(Index), "Triangle must be three packed vertex ids");

constexpr int kThreadsPerBlock = 256;

struct Vec3Min {
  SNAG_HD_INLINE Vec3 operator()(const Vec3& a, const Vec3& b) const { return min(a, b); }
};
struct Vec3Max {
  SNAG_HD_INLINE Vec3 operator()(const Vec3& a, const Vec3& b) const { return max(a, b); }
};

/// One thread per triangle: radius of its sphere at t0 and of its swept sphere.
__global__ void triangle_radii_kernel(const Vec3* __restrict__ x_t0, const Vec3* __restrict__ x_t1,
                                      const Index* __restrict__ corners, std::size_t triangle_count,
                                      double* __restrict__ static_radii, double* __restrict__ swept_radii) {
  const std::size_t stride = static_cast<std::size_t>(gridDim.x) * blockDim.x;
  for (std::size_t f = static_cast<std::size_t>(blockIdx.x) * blockDim.x + threadIdx.x; f < triangle_count;
       f += stride) {
    const Index a = corners[3 * f], b = corners[3 * f + 1], c = corners[3 * f + 2];
    const TriangleSphere s_t0 = centroid_sphere(x_t0[a], x_t0[b], x_t0[c]);
    const TriangleSphere s_t1 = centroid_sphere(x_t1[a], x_t1[b], x_t1[c]);
    static_radii[f] = s_t0.radius;
    swept_radii[f] = enclosing_sphere(s_t0, s_t1).radius;
  }
}

}  // namespace

void triangle_bounds_on_device(const Vec3* positions, std::size_t vertex_count, const Triangle* triangles,
                               std::size_t triangle_count, double* static_radii, double* swept_radii,
                               DeviceBoundsSums* sums, DeviceBuffer<unsigned char>& temp_storage,
                               cudaStream_t stream) {
  assert(vertex_count > 0);
  if (triangle_count > 0) {
    const std::size_t blocks = std::min<std::size_t>((triangle_count + kThreadsPerBlock - 1) / kThreadsPerBlock,
                                                     std::size_t{1} << 30);
    triangle_radii_kernel<<<static_cast<unsigned>(blocks), kThreadsPerBlock, 0, stream>>>(
        positions, positions + vertex_count, reinterpret_cast<const Index*>(triangles), triangle_count,
        static_radii, swept_radii);
    SNAG_CUDA_CHECK_LAUNCH();
  }

  const double inf = std::numeric_limits<double>::infinity();
  const Vec3 lo_init{inf, inf, inf}, hi_init{-inf, -inf, -inf};
  const int position_items = static_cast<int>(2 * vertex_count);
  const int triangle_items = static_cast<int>(triangle_count);
  assert(2 * vertex_count <= static_cast<std::size_t>(std::numeric_limits<int>::max()));

  // Temporary storage: the largest that any of the four reductions asks for.
  std::size_t need = 0, bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(nullptr, bytes, positions, &sums->lo, position_items, Vec3Min{},
                                            lo_init, stream));
  need = std::max(need, bytes);
  SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(nullptr, bytes, positions, &sums->hi, position_items, Vec3Max{},
                                            hi_init, stream));
  need = std::max(need, bytes);
  SNAG_CUDA_CHECK(
      cub::DeviceReduce::Sum(nullptr, bytes, static_radii, &sums->static_radius_sum, triangle_items, stream));
  need = std::max(need, bytes);
  SNAG_CUDA_CHECK(
      cub::DeviceReduce::Sum(nullptr, bytes, swept_radii, &sums->swept_radius_sum, triangle_items, stream));
  need = std::max(need, bytes);
  // A null pointer would turn the calls below into size queries: keep at least one byte.
  if (temp_storage.size() < std::max<std::size_t>(need, 1)) temp_storage.resize(std::max<std::size_t>(need, 1));

  void* temp = temp_storage.data();
  bytes = temp_storage.size();
  SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(temp, bytes, positions, &sums->lo, position_items, Vec3Min{},
                                            lo_init, stream));
  bytes = temp_storage.size();
  SNAG_CUDA_CHECK(cub::DeviceReduce::Reduce(temp, bytes, positions, &sums->hi, position_items, Vec3Max{},
                                            hi_init, stream));
  bytes = temp_storage.size();
  SNAG_CUDA_CHECK(
      cub::DeviceReduce::Sum(temp, bytes, static_radii, &sums->static_radius_sum, triangle_items, stream));
  bytes = temp_storage.size();
  SNAG_CUDA_CHECK(
      cub::DeviceReduce::Sum(temp, bytes, swept_radii, &sums->swept_radius_sum, triangle_items, stream));
}

TriangleBounds compute_triangle_bounds_cuda(const std::vector<Vec3>& x_t0, const std::vector<Vec3>& x_t1,
                                            const std::vector<Triangle>& triangles, double lambda,
                                            CUstream_st* stream_handle) {
  assert(x_t0.size() == x_t1.size());
  assert(lambda > 1.0);
#ifndef NDEBUG
  for (const Triangle& t : triangles) assert(t[0] < x_t0.size() && t[1] < x_t0.size() && t[2] < x_t0.size());
#endif
  const cudaStream_t stream = stream_handle;
  const std::size_t vertex_count = x_t0.size();
  const std::size_t triangle_count = triangles.size();
  TriangleBounds result;
  if (vertex_count == 0) return result;

  CudaEvent start, uploaded, computed, downloaded;
  start.record(stream);
  DeviceBuffer<Vec3> positions(2 * vertex_count, stream);
  SNAG_CUDA_CHECK(cudaMemcpyAsync(positions.data(), x_t0.data(), vertex_count * sizeof(Vec3),
                                  cudaMemcpyHostToDevice, stream));
  SNAG_CUDA_CHECK(cudaMemcpyAsync(positions.data() + vertex_count, x_t1.data(), vertex_count * sizeof(Vec3),
                                  cudaMemcpyHostToDevice, stream));
  DeviceBuffer<Triangle> device_triangles(0, stream);
  device_triangles.upload(triangles);
  uploaded.record(stream);

  DeviceBuffer<double> static_radii(triangle_count, stream), swept_radii(triangle_count, stream);
  DeviceBuffer<DeviceBoundsSums> sums(1, stream);
  DeviceBuffer<unsigned char> temp_storage(0, stream);
  triangle_bounds_on_device(positions.data(), vertex_count, device_triangles.data(), triangle_count,
                            static_radii.data(), swept_radii.data(), sums.data(), temp_storage, stream);
  computed.record(stream);

  result.static_radii.resize(triangle_count);
  result.swept_radii.resize(triangle_count);
  static_radii.download(result.static_radii.data(), triangle_count);
  swept_radii.download(result.swept_radii.data(), triangle_count);
  DeviceBoundsSums host_sums{};
  sums.download(&host_sums, 1);
  downloaded.record(stream);
  SNAG_CUDA_CHECK(cudaStreamSynchronize(stream));

  result.scene_lo = host_sums.lo;
  result.scene_hi = host_sums.hi;
  if (triangle_count > 0) {
    result.mean_static_radius = host_sums.static_radius_sum / static_cast<double>(triangle_count);
    result.mean_swept_radius = host_sums.swept_radius_sum / static_cast<double>(triangle_count);
  }
  result.cell_size = 3.0 * lambda * result.mean_swept_radius;
  result.timings.upload_ms = CudaEvent::elapsed_ms(start, uploaded);
  result.timings.kernels_ms = CudaEvent::elapsed_ms(uploaded, computed);
  result.timings.download_ms = CudaEvent::elapsed_ms(computed, downloaded);
  return result;
}

}  // namespace snag
