// See triangle_separation.cuh.
#include "libcd/cuda/triangle_separation.cuh"

#include <cub/device/device_select.cuh>

#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/launch.cuh"
#include "libcd/narrow_phase/ccd_separating_direction.hpp"

namespace snag {
namespace {

/// A thread a pair: left[p] is 0 where the pair is proven apart, else 1.
/// Four blocks a multiprocessor: 64 registers a thread (sm_90), the corners
/// held in floats, 128 bytes spilled; at three blocks (80 registers, no
/// spills) the kernel ran longer (H100: cloth_ball 0.209 -> 0.196 ms a step,
/// ×4 0.987 -> 0.934, ×16 7.27 -> 6.63; in doubles it took 0.318, 1.483
/// and 10.58 at two blocks).
__global__ void __launch_bounds__(detail::kBlockSize, 4)
    separated_kernel(TriangleSeparation separation, const Triangle* __restrict__ triangles,
                     const TrianglePair* __restrict__ pairs, std::size_t n, std::uint16_t* left) {
  const std::uint64_t p = detail::thread_item();
  if (p >= n) return;
  const TrianglePair pair = pairs[p];
  const Triangle ta = triangles[pair.a], tb = triangles[pair.b];
  const auto corner = [&](int c, int i) {
    return (c % 2 == 0 ? separation.x_t0 : separation.x_t1)[(c < 2 ? ta : tb)[i]];
  };
  left[p] = triangles_separated_by(corner, separation.thickness) ? 0 : 1;
}

}  // namespace

std::size_t remove_separated_pairs_on_device(const TriangleSeparation& separation, const Triangle* triangles,
                                             TrianglePair* pairs, std::size_t n, std::uint16_t* flags,
                                             unsigned long long* selected, DeviceBuffer<unsigned char>& temp,
                                             cudaStream_t stream) {
  if (n == 0) return 0;
  separated_kernel<<<detail::blocks_for(n), detail::kBlockSize, 0, stream>>>(separation, triangles, pairs, n, flags);
  SNAG_CUDA_CHECK_LAUNCH();
  // CUB's stable selection, in place: the pairs left keep their order.
  const auto items = static_cast<::cuda::std::int64_t>(n);
  std::size_t bytes = 0;
  SNAG_CUDA_CHECK(cub::DeviceSelect::Flagged(nullptr, bytes, pairs, flags, selected, items, stream));
  detail::ensure_scratch(temp, bytes);
  bytes = temp.size();
  SNAG_CUDA_CHECK(cub::DeviceSelect::Flagged(temp.data(), bytes, pairs, flags, selected, items, stream));
  unsigned long long left = 0;
  ReadBack(stream).add(&left, selected).wait();
  return static_cast<std::size_t>(left);
}

}  // namespace snag
