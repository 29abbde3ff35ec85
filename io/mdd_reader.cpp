#include "io/mdd_reader.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "io/reader_support.hpp"
#include "libcd/core/error.hpp"

namespace snag::io {

static std::int32_t load_big_endian_int32(const char* at) {
  std::uint32_t bits;
  std::memcpy(&bits, at, 4);
  return static_cast<std::int32_t>(__builtin_bswap32(bits));
}

PointCacheLayout parse_mdd_layout(std::string_view bytes, const std::string& file) {
  auto fail = [&](std::size_t byte, const std::string& message) {
    InputLocation where{file};
    where.byte = byte;
    throw InputError(where, message);
  };
  if (bytes.size() < 8) fail(bytes.size(), "truncated: an MDD header needs 8 bytes");
  const std::int32_t frames = load_big_endian_int32(bytes.data());
  const std::int32_t points = load_big_endian_int32(bytes.data() + 4);
  if (frames <= 0) fail(0, "frame count " + std::to_string(frames) + " (must be positive)");
  if (points <= 0) fail(4, "point count " + std::to_string(points) + " (must be positive)");
  const std::uint64_t frame_bytes = 12ull * static_cast<std::uint64_t>(points);
  const std::uint64_t data_offset = 8 + 4ull * static_cast<std::uint64_t>(frames);
  const std::uint64_t animated = data_offset + frame_bytes * static_cast<std::uint64_t>(frames);
  const std::uint64_t with_rest = animated + frame_bytes;
  PointCacheLayout layout;
  if (bytes.size() == animated) {
    layout.first_frame_offset = static_cast<std::size_t>(data_offset);
  } else if (bytes.size() == with_rest) {
    layout.first_frame_offset = static_cast<std::size_t>(data_offset + frame_bytes);
  } else {
    fail(bytes.size() < animated ? bytes.size() : animated,
         "header says " + with_thousands(static_cast<std::size_t>(frames)) + " frames of " +
             with_thousands(static_cast<std::size_t>(points)) + " points (" + with_thousands(animated) + " bytes, or " +
             with_thousands(with_rest) + " with a rest frame) but the file has " + with_thousands(bytes.size()) +
             " bytes");
  }
  layout.point_count = static_cast<std::size_t>(points);
  layout.frame_count = static_cast<std::size_t>(frames);
  layout.big_endian = true;
  layout.times_offset = 8;
  for (std::size_t i = 0; i < layout.frame_count; ++i) {
    if (!std::isfinite(point_cache_frame_time(bytes, layout, i))) fail(8 + 4 * i, "time of frame " + std::to_string(i) + " is not finite");
  }
  return layout;
}

}  // namespace snag::io
