// See triangle_separation.cuh.
#include "libcd/cuda/triangle_separation.cuh"

#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/device_scan.cuh"
#include "libcd/cuda/launch.cuh"
#include "libcd/narrow_phase/ccd_separating_direction.hpp"

namespace snag {
namespace {

/// A thread a key: its pair is appended to `out` (a warp's with one
/// atomic) unless proven apart. Four blocks a multiprocessor: 64 registers a
/// thread (sm_90), the corners held in floats, 128 bytes spilled; at three
/// blocks (80 registers, no spills) the test ran longer (H100, as a kernel
/// of its own over the pairs: cloth_ball 0.209 -> 0.196 ms a step, ×4 0.987
/// -> 0.934, ×16 7.27 -> 6.63; in doubles it took 0.318, 1.483 and 10.58 at
/// two blocks). Written where the keys are unpacked, the test saves the
/// pairs' own pass, its flags and their selection (device time a step,
/// H100: ×16 54.8 -> 53.8 ms, ×4 9.80 -> 9.61). Run earlier, in the pair
/// tests (test_kernel), on the pairs of two whole roots before their keys
/// were kept, it left ×16 one chunk instead of three but took test_kernel
/// from 19 to 54 ms a step (H100; the same counts and events), against
/// the 7.4 ms of this kernel (there it spills at the pair tests' 56
/// registers, inlined or not).
__global__ void __launch_bounds__(detail::kBlockSize, 4)
    unseparated_kernel(TriangleSeparation separation, const Triangle* __restrict__ triangles,
                       const std::uint64_t* __restrict__ keys, std::size_t n, int key_bits, TrianglePair* out,
                       unsigned long long* written) {
  const std::uint64_t k = detail::thread_item();
  TrianglePair pair{};
  bool left = false;
  if (k < n) {
    detail::unpack_key(keys[k], key_bits, pair.a, pair.b);
    const Triangle ta = triangles[pair.a], tb = triangles[pair.b];
    const auto corner = [&](int c, int i) {
      return (c % 2 == 0 ? separation.x_t0 : separation.x_t1)[(c < 2 ? ta : tb)[i]];
    };
    left = !triangles_separated_by(corner, separation.thickness);
  }
  const unsigned long long slot = detail::warp_append(left, written);  // every lane of the warp
  if (left) out[slot] = pair;
}

}  // namespace

void append_unseparated_pairs_on_device(const TriangleSeparation& separation, const Triangle* triangles,
                                        const std::uint64_t* keys, std::size_t n, int key_bits, TrianglePair* out,
                                        unsigned long long* written, cudaStream_t stream) {
  if (n == 0) return;
  unseparated_kernel<<<detail::blocks_for(n), detail::kBlockSize, 0, stream>>>(separation, triangles, keys, n,
                                                                              key_bits, out, written);
  SNAG_CUDA_CHECK_LAUNCH();
}

}  // namespace snag
