// The triangle pairs' separation test of the feature stage on the GPU
// (TriangleSeparation, libcd/culling/representative_triangles.hpp): a thread
// a pair runs triangles_separated, the CPU's test, and the pairs it proves
// apart are removed before count_kernel (representative_triangles.cuh) makes
// the pairs' feature pairs, so that the stages after it run over those left
// (cloth_ball 36% of the unique pairs, ×4 21%, ×16 11%). This file is
// compiled without fused multiply-adds (libcd/cuda/CMakeLists.txt), so each
// decision is the CPU back end's and the two back ends' candidates and
// counts are the same.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>

#include "libcd/broad_phase/candidates.hpp"
#include "libcd/cuda/device_buffer.cuh"
#include "libcd/culling/representative_triangles.hpp"

namespace snag {

/// Removes from pairs[0, n) those whose triangles `separation` (device
/// positions) proves apart over its step, in place and in their order, and
/// returns how many are left. `flags` (n of them), `selected` (one counter)
/// and `temp` are its device scratch. Waits for the stream. Throws CudaError.
std::size_t remove_separated_pairs_on_device(const TriangleSeparation& separation, const Triangle* triangles,
                                             TrianglePair* pairs, std::size_t n, std::uint16_t* flags,
                                             unsigned long long* selected, DeviceBuffer<unsigned char>& temp,
                                             cudaStream_t stream);

}  // namespace snag
