// Accounting of the device memory that the CUDA back end allocates through
// DeviceBuffer: bytes held now and the peak since the last reset. The product
// reports the peak device memory of a scan; plain C++ so the tools can read it.
#pragma once

#include <atomic>
#include <cstddef>

namespace snag {

/// Process-wide counter of device bytes held by DeviceBuffer objects. Thread-safe.
/// With the environment variable SNAG_DEVICE_MEMORY_LOG set, every allocation
/// of 64 MiB or more is printed on standard error with the stage of the
/// calling thread (set_stage) and the bytes held after it: where the device
/// memory of a large scene goes.
/// Counts what the buffers asked for (their capacity), not what the CUDA
/// memory pool keeps in reserve, nor memory that libraries allocate themselves
/// outside DeviceBuffer (temporary storage is allocated through DeviceBuffer too).
class DeviceMemoryTracker {
 public:
  /// The one tracker of the process.
  static DeviceMemoryTracker& instance();

  /// Records an allocation of `bytes` (after it succeeded).
  void on_allocate(std::size_t bytes);
  /// Records that `bytes` previously recorded by on_allocate were freed.
  void on_free(std::size_t bytes);

  /// Bytes held now.
  std::size_t current_bytes() const { return current_.load(); }
  /// Largest current_bytes() seen since construction or the last reset_peak().
  std::size_t peak_bytes() const { return peak_.load(); }
  /// Starts a new measurement: the peak becomes the bytes held now.
  void reset_peak() { peak_.store(current_.load()); }

  /// Names what the calling thread allocates for next (a string literal), for the log.
  static void set_stage(const char* stage);

 private:
  DeviceMemoryTracker() = default;
  std::atomic<std::size_t> current_{0};
  std::atomic<std::size_t> peak_{0};
};

}  // namespace snag
