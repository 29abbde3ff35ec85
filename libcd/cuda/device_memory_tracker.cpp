#include "libcd/cuda/device_memory_tracker.hpp"

#include <cassert>
#include <cstdio>
#include <cstdlib>

namespace snag {

DeviceMemoryTracker& DeviceMemoryTracker::instance() {
  static DeviceMemoryTracker tracker;
  return tracker;
}

namespace {

thread_local const char* current_stage = "other";

bool log_enabled() {
  static const bool enabled = std::getenv("SNAG_DEVICE_MEMORY_LOG") != nullptr;
  return enabled;
}

}  // namespace

void DeviceMemoryTracker::set_stage(const char* stage) { current_stage = stage; }

void DeviceMemoryTracker::on_allocate(std::size_t bytes) {
  const std::size_t now = current_.fetch_add(bytes) + bytes;
  if (log_enabled() && bytes >= (std::size_t{64} << 20))
    std::fprintf(stderr, "device memory: %s +%.1f MiB, %.1f MiB held\n", current_stage, bytes / 1048576.0,
                 now / 1048576.0);
  std::size_t peak = peak_.load();
  while (now > peak && !peak_.compare_exchange_weak(peak, now)) {
  }
}

void DeviceMemoryTracker::on_free(std::size_t bytes) {
  [[maybe_unused]] const std::size_t before = current_.fetch_sub(bytes);
  assert(before >= bytes && "freeing more device bytes than were recorded");
}

}  // namespace snag
