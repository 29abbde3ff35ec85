// See triangle_separation.cuh.
#include "libcd/cuda/triangle_separation.cuh"

#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/launch.cuh"
#include "libcd/narrow_phase/ccd_separating_direction.hpp"

namespace snag {
namespace {

/// A thread a pair. Two blocks a multiprocessor: unbounded, the compiler
/// takes 138 registers a thread (one block); at 128 it spills 16 bytes
/// (sm_90). The bound is chosen from these counts, not yet from timings.
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
