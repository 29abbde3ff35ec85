// A move-only owner of a CUDA event, for timing work on a stream.
#pragma once

#include <cuda_runtime_api.h>

#include <utility>

#include "libcd/cuda/cuda_check.cuh"

namespace snag {

class CudaEvent {
 public:
  /// Creates a timing event. Throws CudaError.
  CudaEvent() { SNAG_CUDA_CHECK(cudaEventCreate(&event_)); }
  ~CudaEvent() {
    if (event_ != nullptr) (void)cudaEventDestroy(event_);
  }
  CudaEvent(const CudaEvent&) = delete;
  CudaEvent& operator=(const CudaEvent&) = delete;
  CudaEvent(CudaEvent&& other) noexcept : event_(std::exchange(other.event_, nullptr)) {}
  CudaEvent& operator=(CudaEvent&& other) noexcept {
    std::swap(event_, other.event_);
    return *this;
  }

  /// Records the event on `stream`. Throws CudaError.
  void record(cudaStream_t stream) { SNAG_CUDA_CHECK(cudaEventRecord(event_, stream)); }
  cudaEvent_t get() const { return event_; }

  /// Milliseconds between two recorded, completed events. Throws CudaError.
  static float elapsed_ms(const CudaEvent& from, const CudaEvent& to) {
    float ms = 0;
    SNAG_CUDA_CHECK(cudaEventElapsedTime(&ms, from.event_, to.event_));
    return ms;
  }

 private:
  cudaEvent_t event_ = nullptr;
};

}  // namespace snag
