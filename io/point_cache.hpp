// Point caches (PC2, MDD): per-frame float32 positions for a topology mesh's
// vertices, read in place from memory so a frame costs only its own bytes.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "libcd/geometry/vec3.hpp"

namespace snag::io {

/// Where a point cache's frames lie in its bytes; made by parse_pc2_layout or
/// parse_mdd_layout, which check it against the byte count.
struct PointCacheLayout {
  std::size_t point_count = 0;
  std::size_t frame_count = 0;
  std::size_t first_frame_offset = 0;  ///< byte offset of frame 0's points
  bool big_endian = false;             ///< float32 byte order (MDD: big, PC2: little)
  /// PC2: frame i is at time first_time + i × time_step (in frames).
  double first_time = 0, time_step = 1;
  /// MDD: byte offset of frame_count big-endian float32 times (seconds); npos for PC2.
  std::size_t times_offset = static_cast<std::size_t>(-1);
};

/// Frame i's time: PC2 in the cache's frame numbering, MDD in seconds as stored.
double point_cache_frame_time(std::string_view bytes, const PointCacheLayout& layout, std::size_t i);

/// Copies frame i's point_count points into `out`, widened exactly to double.
/// `bytes` is the whole file the layout was made from; i < frame_count.
/// Throws InputError (naming `file`, the frame and the byte) for a NaN/Inf coordinate.
void read_point_cache_frame(std::string_view bytes, const PointCacheLayout& layout, std::size_t i, Vec3* out,
                            const std::string& file);

}  // namespace snag::io
