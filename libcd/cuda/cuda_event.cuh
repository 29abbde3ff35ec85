// A move-only owner of a CUDA event, for timing work on a stream.
#pragma once

#include <cuda_runtime_api.h>

#include <cstddef>
#include <utility>
#include <vector>

#include "libcd/cuda/cuda_check.cuh"

namespace snag {

/// A timing event. Events are taken from a pool of the calling thread's and
/// given back to the pool of the thread that lets them go, not created and
/// destroyed: each of those is a driver call that waits for the driver's
/// lock, up to tens of microseconds while another thread launches work, and a
/// detection times each of its stages and rounds.
class CudaEvent {
 public:
  /// A timing event of the current device. Throws CudaError.
  CudaEvent() : event_(take(device_)) {}
  ~CudaEvent() {
    if (event_ != nullptr) give_back(device_, event_);
  }
  CudaEvent(const CudaEvent&) = delete;
  CudaEvent& operator=(const CudaEvent&) = delete;
  CudaEvent(CudaEvent&& other) noexcept : device_(other.device_), event_(std::exchange(other.event_, nullptr)) {}
  CudaEvent& operator=(CudaEvent&& other) noexcept {
    std::swap(device_, other.device_);
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
  struct Pooled {
    int device;
    cudaEvent_t event;
  };
  /// A thread's idle events, at most kMostPooled; destroyed with the thread.
  struct Pool {
    std::vector<Pooled> idle;
    Pool() = default;
    Pool(const Pool&) = delete;
    Pool& operator=(const Pool&) = delete;
    ~Pool() {
      for (const Pooled& pooled : idle) (void)cudaEventDestroy(pooled.event);
    }
  };
  static constexpr std::size_t kMostPooled = 64;
  static Pool& thread_pool() {
    thread_local Pool pool;
    return pool;
  }
  static cudaEvent_t take(int& device) {
    SNAG_CUDA_CHECK(cudaGetDevice(&device));
    std::vector<Pooled>& idle = thread_pool().idle;
    for (std::size_t k = idle.size(); k-- > 0;) {
      if (idle[k].device != device) continue;
      const cudaEvent_t event = idle[k].event;
      idle[k] = idle.back();
      idle.pop_back();
      return event;
    }
    cudaEvent_t event = nullptr;
    SNAG_CUDA_CHECK(cudaEventCreate(&event));
    return event;
  }
  static void give_back(int device, cudaEvent_t event) noexcept {
    std::vector<Pooled>& idle = thread_pool().idle;
    if (idle.size() < kMostPooled) {
      try {
        idle.push_back(Pooled{device, event});
        return;
      } catch (...) {  // no room to keep it: it goes
      }
    }
    (void)cudaEventDestroy(event);
  }

  int device_ = 0;
  cudaEvent_t event_ = nullptr;
};

}  // namespace snag
