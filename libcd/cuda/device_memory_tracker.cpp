#include "libcd/cuda/device_memory_tracker.hpp"

#include <cassert>

namespace snag {

DeviceMemoryTracker& DeviceMemoryTracker::instance() {
  static DeviceMemoryTracker tracker;
  return tracker;
}

void DeviceMemoryTracker::on_allocate(std::size_t bytes) {
  const std::size_t now = current_.fetch_add(bytes) + bytes;
  std::size_t peak = peak_.load();
  while (now > peak && !peak_.compare_exchange_weak(peak, now)) {
  }
}

void DeviceMemoryTracker::on_free(std::size_t bytes) {
  [[maybe_unused]] const std::size_t before = current_.fetch_sub(bytes);
  assert(before >= bytes && "freeing more device bytes than were recorded");
}

}  // namespace snag
