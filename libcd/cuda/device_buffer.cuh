// Owners of device and pinned host memory for the CUDA back end.
//
// DeviceBuffer<T>: a move-only array in device memory, allocated and freed in
// stream order (cudaMallocAsync / cudaFreeAsync) on the stream it was made
// for, with uploads and downloads on that stream. Every byte it holds is
// recorded in DeviceMemoryTracker, so the peak device memory of a run is known.
// PinnedBuffer<T>: a move-only array in page-locked host memory, the staging
// area for truly asynchronous uploads of streamed frames.
// ReadBack: small device values copied to the host with one wait.
//
// T must be trivially copyable: contents move by memcpy.
#pragma once

#include <cuda_runtime_api.h>

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstring>
#include <functional>
#include <type_traits>
#include <utility>
#include <vector>

#include "libcd/cuda/cuda_check.cuh"
#include "libcd/cuda/device_memory_tracker.hpp"

namespace snag {

template <class T>
class DeviceBuffer {
  static_assert(std::is_trivially_copyable<T>::value, "DeviceBuffer holds trivially copyable types only");

 public:
  DeviceBuffer() = default;
  /// An uninitialised buffer of `count` elements, allocated on `stream`.
  /// Throws CudaError when the allocation fails.
  explicit DeviceBuffer(std::size_t count, cudaStream_t stream = nullptr) : stream_(stream) { resize(count); }
  ~DeviceBuffer() { release(); }

  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;
  DeviceBuffer(DeviceBuffer&& other) noexcept { take(other); }
  DeviceBuffer& operator=(DeviceBuffer&& other) noexcept {
    if (this != &other) {
      release();
      take(other);
    }
    return *this;
  }

  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::size_t size_bytes() const { return size_ * sizeof(T); }
  /// Elements the current allocation can hold without reallocating.
  std::size_t capacity() const { return capacity_; }
  /// Device bytes the buffer holds (its capacity).
  std::size_t capacity_bytes() const { return capacity_ * sizeof(T); }
  cudaStream_t stream() const { return stream_; }
  /// Device bytes resize(count) would add to what the buffer holds.
  std::size_t growth_bytes(std::size_t count) const { return count > capacity_ ? (count - capacity_) * sizeof(T) : 0; }

  /// Sets the size to `count`, discarding the contents (nothing is copied).
  /// Reallocates only when `count` exceeds the capacity. Throws CudaError.
  void resize(std::size_t count) {
    if (count > capacity_) {
      release();
      void* p = nullptr;
      SNAG_CUDA_CHECK(cudaMallocAsync(&p, count * sizeof(T), stream_));
      data_ = static_cast<T*>(p);
      capacity_ = count;
      DeviceMemoryTracker::instance().on_allocate(capacity_ * sizeof(T));
    }
    size_ = count;
  }

  /// Frees the memory now (in stream order); the buffer becomes empty.
  void release() noexcept {
    if (data_ != nullptr) {
      // A destructor cannot throw; a failed free leaves the pool to reclaim it.
      (void)cudaFreeAsync(data_, stream_);
      DeviceMemoryTracker::instance().on_free(capacity_ * sizeof(T));
    }
    data_ = nullptr;
    size_ = capacity_ = 0;
  }

  /// Resizes to `count` and copies `count` elements from host memory, in
  /// stream order. From pageable memory the call returns once `host` may be
  /// reused; from a PinnedBuffer it returns at once. Throws CudaError.
  void upload(const T* host, std::size_t count) {
    resize(count);
    if (count > 0) SNAG_CUDA_CHECK(cudaMemcpyAsync(data_, host, size_bytes(), cudaMemcpyHostToDevice, stream_));
  }
  void upload(const std::vector<T>& host) { upload(host.data(), host.size()); }

  /// Copies the first `count` (≤ size()) elements to host memory in stream
  /// order; the caller synchronises the stream before reading `host`. Throws CudaError.
  void download(T* host, std::size_t count) const {
    assert(count <= size_);
    if (count > 0) SNAG_CUDA_CHECK(cudaMemcpyAsync(host, data_, count * sizeof(T), cudaMemcpyDeviceToHost, stream_));
  }
  /// All elements, copied to a new vector; waits for the stream. Throws CudaError.
  std::vector<T> download() const {
    std::vector<T> host(size_);
    download(host.data(), size_);
    SNAG_CUDA_CHECK(cudaStreamSynchronize(stream_));
    return host;
  }

  /// Sets every byte to zero, in stream order. Throws CudaError.
  void fill_zero() {
    if (size_ > 0) SNAG_CUDA_CHECK(cudaMemsetAsync(data_, 0, size_bytes(), stream_));
  }

 private:
  void take(DeviceBuffer& other) noexcept {
    data_ = std::exchange(other.data_, nullptr);
    size_ = std::exchange(other.size_, 0);
    capacity_ = std::exchange(other.capacity_, 0);
    stream_ = other.stream_;
  }

  T* data_ = nullptr;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
  cudaStream_t stream_ = nullptr;
};

template <class T>
class PinnedBuffer {
  static_assert(std::is_trivially_copyable<T>::value, "PinnedBuffer holds trivially copyable types only");

 public:
  PinnedBuffer() = default;
  /// An uninitialised page-locked host array of `count` elements. Throws CudaError.
  explicit PinnedBuffer(std::size_t count) { resize(count); }
  ~PinnedBuffer() { release(); }

  PinnedBuffer(const PinnedBuffer&) = delete;
  PinnedBuffer& operator=(const PinnedBuffer&) = delete;
  PinnedBuffer(PinnedBuffer&& other) noexcept { take(other); }
  PinnedBuffer& operator=(PinnedBuffer&& other) noexcept {
    if (this != &other) {
      release();
      take(other);
    }
    return *this;
  }

  T* data() { return data_; }
  const T* data() const { return data_; }
  std::size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }
  T* begin() { return data_; }
  T* end() { return data_ + size_; }

  /// Sets the size to `count`, discarding the contents; reallocates only when
  /// `count` exceeds the capacity. Throws CudaError.
  void resize(std::size_t count) {
    if (count > capacity_) {
      release();
      void* p = nullptr;
      SNAG_CUDA_CHECK(cudaMallocHost(&p, count * sizeof(T)));
      data_ = static_cast<T*>(p);
      capacity_ = count;
    }
    size_ = count;
  }

  void release() noexcept {
    if (data_ != nullptr) (void)cudaFreeHost(data_);
    data_ = nullptr;
    size_ = capacity_ = 0;
  }

 private:
  void take(PinnedBuffer& other) noexcept {
    data_ = std::exchange(other.data_, nullptr);
    size_ = std::exchange(other.size_, 0);
    capacity_ = std::exchange(other.capacity_, 0);
  }

  T* data_ = nullptr;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

/// A few small device values (counts, totals, counters) copied to the host
/// with one wait. A copy to pageable memory returns only once it is done, so
/// that each would wait for the device on its own; these copies land in
/// page-locked memory of the calling thread instead, and wait() waits for
/// them once and moves each value to its place. start() enqueues the copies
/// alone, so that work the values do not decide can be enqueued behind them
/// before wait() (one started ReadBack per thread at a time: they share the
/// thread's page-locked memory).
class ReadBack {
 public:
  explicit ReadBack(cudaStream_t stream) : stream_(stream) {}

  /// Copies device[0, count) to host[0, count) at wait().
  template <class T>
  ReadBack& add(T* host, const T* device, std::size_t count = 1) {
    static_assert(std::is_trivially_copyable<T>::value, "ReadBack copies trivially copyable types only");
    assert(copies_ < kMaxCopies && !started_);
    copy_[copies_++] = Copy{host, device, count * sizeof(T)};
    return *this;
  }

  /// Enqueues the copies and marks their end. Throws CudaError.
  ReadBack& start() {
    assert(!started_);
    Staging& staging = thread_staging();
    std::size_t total = 0;
    for (int k = 0; k < copies_; ++k) total += (copy_[k].bytes + kAlign - 1) / kAlign * kAlign;
    staging.memory.resize(total);
    std::size_t at = 0;
    for (int k = 0; k < copies_; ++k) {
      if (copy_[k].bytes > 0)
        SNAG_CUDA_CHECK(cudaMemcpyAsync(staging.memory.data() + at, copy_[k].device, copy_[k].bytes,
                                        cudaMemcpyDeviceToHost, stream_));
      at += (copy_[k].bytes + kAlign - 1) / kAlign * kAlign;
    }
    SNAG_CUDA_CHECK(cudaEventRecord(staging.copied, stream_));
    started_ = true;
    return *this;
  }

  /// Waits for the copies (enqueued first if start() was not called) and
  /// moves the values to their places. Throws CudaError.
  void wait() {
    if (!started_) start();
    Staging& staging = thread_staging();
    SNAG_CUDA_CHECK(cudaEventSynchronize(staging.copied));
    std::size_t at = 0;
    for (int k = 0; k < copies_; ++k) {
      if (copy_[k].bytes > 0) std::memcpy(copy_[k].host, staging.memory.data() + at, copy_[k].bytes);
      at += (copy_[k].bytes + kAlign - 1) / kAlign * kAlign;
    }
    copies_ = 0;
    started_ = false;
  }

 private:
  static constexpr int kMaxCopies = 4;
  static constexpr std::size_t kAlign = 16;
  struct Copy {
    void* host;
    const void* device;
    std::size_t bytes;
  };
  /// The calling thread's page-locked memory and the event after its copies.
  struct Staging {
    PinnedBuffer<unsigned char> memory;
    cudaEvent_t copied = nullptr;
    Staging() { SNAG_CUDA_CHECK(cudaEventCreateWithFlags(&copied, cudaEventDisableTiming)); }
    ~Staging() {
      if (copied != nullptr) (void)cudaEventDestroy(copied);
    }
    Staging(const Staging&) = delete;
    Staging& operator=(const Staging&) = delete;
  };
  static Staging& thread_staging() {
    thread_local Staging staging;
    return staging;
  }

  cudaStream_t stream_;
  Copy copy_[kMaxCopies] = {};
  int copies_ = 0;
  bool started_ = false;
};

/// Told by a stage the device bytes its buffers are about to add, before they
/// allocate, so that a memory budget is checked before it is exceeded (the
/// CUDA broad phase throws a UsageError there). An empty check accepts all.
using GrowthCheck = std::function<void(std::size_t bytes)>;
inline void check_growth(const GrowthCheck& check, std::size_t bytes) {
  if (check) check(bytes);
}

/// Gives `buffer` room for `count` items keeping its first `kept` (a list that
/// grows stage after stage): when the capacity is short, `spare` is sized to
/// max(count, twice the capacity), takes the kept items and becomes the
/// buffer; `check` is told first. The size becomes `count`. Throws CudaError.
template <class T>
void grow_keeping(DeviceBuffer<T>& buffer, DeviceBuffer<T>& spare, std::size_t kept, std::size_t count,
                  const GrowthCheck& check = {}) {
  if (count > buffer.capacity()) {
    const std::size_t room = std::max<std::size_t>(count, 2 * buffer.capacity());
    check_growth(check, spare.growth_bytes(room));  // beside the kept items, which it takes over
    spare.resize(room);
    if (kept > 0)
      SNAG_CUDA_CHECK(cudaMemcpyAsync(spare.data(), buffer.data(), kept * sizeof(T), cudaMemcpyDeviceToDevice,
                                      buffer.stream()));
    std::swap(buffer, spare);
    spare.release();
  }
  buffer.resize(count);
}

}  // namespace snag
