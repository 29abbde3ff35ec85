// Checks around every CUDA runtime call and kernel launch: a failure throws
// snag::CudaError naming the call, the file and line, and CUDA's own words.
// Pattern after scalable-ccd's cuda/utils/assert.cuh.
#pragma once

#include <cuda_runtime_api.h>

#include <string>

#include "libcd/cuda/cuda_error.hpp"

namespace snag::detail {

/// Throws CudaError when `status` is not cudaSuccess; `call` is the source text.
inline void throw_on_cuda_error(cudaError_t status, const char* call, const char* file, int line) {
  if (status == cudaSuccess) return;
  // Clear the (non-sticky) error so that a later, unrelated check does not report it again.
  (void)cudaGetLastError();
  throw CudaError(std::string(file) + ":" + std::to_string(line) + ": " + call + " failed: " +
                      cudaGetErrorName(status) + " (" + cudaGetErrorString(status) + ")",
                  static_cast<int>(status));
}

}  // namespace snag::detail

/// Evaluates a CUDA runtime call; throws snag::CudaError when it does not return cudaSuccess.
#define SNAG_CUDA_CHECK(call) ::snag::detail::throw_on_cuda_error((call), #call, __FILE__, __LINE__)

/// Checks the kernel launch just made (configuration errors); in debug builds
/// (NDEBUG not defined) also waits for the device, so that faults inside the
/// kernel are reported at the launch that caused them.
#ifdef NDEBUG
#define SNAG_CUDA_CHECK_LAUNCH() SNAG_CUDA_CHECK(cudaGetLastError())
#else
#define SNAG_CUDA_CHECK_LAUNCH()              \
  do {                                        \
    SNAG_CUDA_CHECK(cudaGetLastError());      \
    SNAG_CUDA_CHECK(cudaDeviceSynchronize()); \
  } while (0)
#endif
