// The triangle pairs' separation test of the feature stage on the GPU
// (TriangleSeparation, libcd/culling/representative_triangles.hpp): a thread
// a pair runs triangles_separated, the CPU's test, before count_kernel
// (representative_triangles.cuh) makes the pair's feature pairs. This file
// is compiled without fused multiply-adds (libcd/cuda/CMakeLists.txt), so
// each decision is the CPU back end's and the two back ends' candidates and
// counts are the same.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>

#include "libcd/broad_phase/candidates.hpp"
#include "libcd/culling/representative_triangles.hpp"

namespace snag {

/// Sets separated[p] to 1 where `separation` (device positions) proves the
/// triangles of pairs[p] apart over its step, else to 0, for every p < n,
/// and adds the pairs set to *count (device). Launches on `stream`, waits
/// for nothing. Throws CudaError.
void mark_separated_pairs_on_device(const TriangleSeparation& separation, const Triangle* triangles,
                                    const TrianglePair* pairs, std::size_t n, std::uint16_t* separated,
                                    unsigned long long* count, cudaStream_t stream);

}  // namespace snag
