// See triangle_separation.cuh.
#include "libcd/cuda/triangle_separation.cuh"

#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/launch.cuh"
#include "libcd/narrow_phase/ccd_separating_direction.hpp"

namespace snag {
namespace {

/// A thread a pair. Two blocks a multiprocessor: 128 registers a thread,
/// no spills (sm_90); three blocks (80 registers) spill 564 bytes. The 12
/// corners in doubles take 72 of them.
__global__ void __launch_bounds__(detail::kBlockSize, 2)
    separated_kernel(TriangleSeparation separation, const Triangle* __restrict__ triangles,
                     const TrianglePair* __restrict__ pairs, std::size_t n, std::uint16_t* separated,
                     unsigned long long* count) {
  const std::uint64_t p = detail::thread_item();
  bool apart = false;
  if (p < n) {
    const TrianglePair pair = pairs[p];
    const Triangle ta = triangles[pair.a], tb = triangles[pair.b];
    Vec3 a_t0[3], a_t1[3], b_t0[3], b_t1[3];
#pragma unroll
    for (int i = 0; i < 3; ++i) {
      a_t0[i] = separation.x_t0[ta[i]];
      a_t1[i] = separation.x_t1[ta[i]];
      b_t0[i] = separation.x_t0[tb[i]];
      b_t1[i] = separation.x_t1[tb[i]];
    }
    apart = triangles_separated(a_t0, a_t1, b_t0, b_t1, separation.thickness);
    separated[p] = apart ? 1 : 0;
  }
  detail::warp_count(apart ? 1u : 0u, count);
}

}  // namespace

void mark_separated_pairs_on_device(const TriangleSeparation& separation, const Triangle* triangles,
                                    const TrianglePair* pairs, std::size_t n, std::uint16_t* separated,
                                    unsigned long long* count, cudaStream_t stream) {
  if (n == 0) return;
  separated_kernel<<<detail::blocks_for(n), detail::kBlockSize, 0, stream>>>(separation, triangles, pairs, n,
                                                                            separated, count);
  SNAG_CUDA_CHECK_LAUNCH();
}

}  // namespace snag
