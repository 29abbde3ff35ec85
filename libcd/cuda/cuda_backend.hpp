// The CUDA back end of the pipeline (cuda_backend.cu): the broad phase, the
// narrow phase on the GPU (libcd/cuda/narrow_phase.cuh), exact certification
// of uncertain CCD answers on the CPU, and events built exactly as the CPU back
// end builds them, so that both return the same event vectors bit for bit.
// Plain C++: no CUDA types.
#pragma once

#include <memory>

#include "libcd/broad_phase/broad_phase.hpp"
#include "libcd/pipeline/backend.hpp"

namespace snag {

/// Makes the CUDA back end ("cuda").
///   broad_phase: [in] the broad phase method (the virtual subdivision grid by
///     default; the largest-triangle grid and brute force for comparisons).
/// The device is used from bind() on; bind() throws CudaError when the scene's
/// topology and three frames do not fit in device memory (the message names the
/// bytes needed and free), and every later call throws CudaError when a CUDA
/// call fails or a buffer cannot grow: never a partial result. Check
/// query_cuda_device() (libcd/cuda/device.hpp) first.
std::unique_ptr<Backend> make_cuda_backend(BroadPhaseMethod broad_phase = BroadPhaseMethod::kVirtualSubdivisionGrid);

}  // namespace snag
