// The triangle pairs' separation test on the GPU (TriangleSeparation,
// libcd/culling/representative_triangles.hpp), run where the pair tests'
// unique keys become pairs: a thread a key runs triangles_separated, the
// CPU's test, and only the pairs it does not prove apart are written, so
// that the feature stage (representative_triangles.cuh) runs over those left
// (cloth_ball 36% of the unique pairs, ×4 21%, ×16 11%). The CPU back end
// runs the same test in its feature stage, on the same pairs. This file is
// compiled without fused multiply-adds (libcd/cuda/CMakeLists.txt), so each
// decision is the CPU back end's and the two back ends' candidates and
// counts are the same.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <cstdint>

#include "libcd/broad_phase/candidates.hpp"
#include "libcd/culling/representative_triangles.hpp"

namespace snag {

/// Appends the pairs of keys[0, n) (pack_key: the smaller root above the
/// larger, key_bits bits each) whose triangles `separation` (device
/// positions) does not prove apart over its step to out, at the places
/// *written counts on (in any order), and adds their count to *written.
/// Launches on `stream` without waiting. Throws CudaError.
void append_unseparated_pairs_on_device(const TriangleSeparation& separation, const Triangle* triangles,
                                        const std::uint64_t* keys, std::size_t n, int key_bits, TrianglePair* out,
                                        unsigned long long* written, cudaStream_t stream);

}  // namespace snag
