#include "io/pc2_reader.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "io/reader_support.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

static constexpr std::size_t pc2_header_size = 32;

PointCacheLayout parse_pc2_layout(std::string_view bytes, const std::string& file) {
  auto fail = [&](std::size_t byte, const std::string& message) {
    InputLocation where{file};
    where.byte = byte;
    throw InputError(where, message);
  };
  if (bytes.size() < pc2_header_size) fail(bytes.size(), "truncated: a PC2 header needs 32 bytes");
  if (std::memcmp(bytes.data(), "POINTCACHE2\0", 12) != 0) fail(0, "not a PC2 file (no POINTCACHE2 signature)");
  std::int32_t version, points, samples;
  float start, rate;
  std::memcpy(&version, bytes.data() + 12, 4);  // little-endian hosts
  std::memcpy(&points, bytes.data() + 16, 4);
  std::memcpy(&start, bytes.data() + 20, 4);
  std::memcpy(&rate, bytes.data() + 24, 4);
  std::memcpy(&samples, bytes.data() + 28, 4);
  if (version != 1) fail(12, "unsupported PC2 version " + std::to_string(version));
  if (points <= 0) fail(16, "point count " + std::to_string(points) + " (must be positive)");
  if (samples <= 0) fail(28, "sample count " + std::to_string(samples) + " (must be positive)");
  if (!std::isfinite(start)) fail(20, "start frame is not finite");
  if (!(rate > 0) || !std::isfinite(rate)) fail(24, "sample rate (frames per sample) must be positive");
  const std::uint64_t expected = pc2_header_size + 12ull * static_cast<std::uint64_t>(points) * static_cast<std::uint64_t>(samples);
  if (expected != bytes.size()) {
    fail(bytes.size() < expected ? bytes.size() : expected,
         "header says " + with_thousands(static_cast<std::size_t>(samples)) + " samples of " +
             with_thousands(static_cast<std::size_t>(points)) + " points (" + with_thousands(expected) +
             " bytes) but the file has " + with_thousands(bytes.size()) + " bytes");
  }
  PointCacheLayout layout;
  layout.point_count = static_cast<std::size_t>(points);
  layout.frame_count = static_cast<std::size_t>(samples);
  layout.first_frame_offset = pc2_header_size;
  layout.big_endian = false;
  layout.first_time = start;
  layout.time_step = rate;
  return layout;
}

}  // namespace snag::io
