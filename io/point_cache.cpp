#include "io/point_cache.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "libcd/core/error.hpp"

namespace snag::io {

static float load_float(const char* at, bool big_endian) {
  std::uint32_t bits;
  std::memcpy(&bits, at, sizeof bits);
  if (big_endian) bits = __builtin_bswap32(bits);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

double point_cache_frame_time(std::string_view bytes, const PointCacheLayout& layout, std::size_t i) {
  if (layout.times_offset == static_cast<std::size_t>(-1)) {
    return layout.first_time + static_cast<double>(i) * layout.time_step;
  }
  return load_float(bytes.data() + layout.times_offset + 4 * i, true);
}

void read_point_cache_frame(std::string_view bytes, const PointCacheLayout& layout, std::size_t i, Vec3* out,
                            const std::string& file) {
  const std::size_t frame_bytes = layout.point_count * 12;
  const char* frame = bytes.data() + layout.first_frame_offset + i * frame_bytes;
  const std::size_t n = layout.point_count;
  if (layout.big_endian) {
    for (std::size_t k = 0; k < n; ++k) {
      out[k] = Vec3{load_float(frame + 12 * k, true), load_float(frame + 12 * k + 4, true),
                    load_float(frame + 12 * k + 8, true)};
    }
  } else {
    for (std::size_t k = 0; k < n; ++k) {
      float xyz[3];
      std::memcpy(xyz, frame + 12 * k, sizeof xyz);  // little-endian hosts
      out[k] = Vec3{xyz[0], xyz[1], xyz[2]};
    }
  }
  // Checked after the copy so the common case stays one tight loop.
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(out[k].x) || !std::isfinite(out[k].y) || !std::isfinite(out[k].z)) {
      InputLocation where{file};
      where.frame = i;
      where.byte = static_cast<std::size_t>(frame - bytes.data()) + 12 * k;
      throw InputError(where, "point " + std::to_string(k) + ": coordinate is not finite (NaN or Inf)");
    }
  }
}

}  // namespace snag::io
