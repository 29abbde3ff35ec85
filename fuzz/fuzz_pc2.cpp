// libFuzzer entry point: the PC2 layout check and every frame's read on
// arbitrary bytes. InputError is the expected answer to bad bytes; any other
// exception, crash or sanitizer report is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "io/pc2_reader.hpp"
#include "libcd/core/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const snag::io::PointCacheLayout layout = snag::io::parse_pc2_layout(bytes, "fuzz.pc2");
    std::vector<snag::Vec3> points(layout.point_count);
    for (std::size_t i = 0; i < layout.frame_count; ++i) {
      (void)snag::io::point_cache_frame_time(bytes, layout, i);
      snag::io::read_point_cache_frame(bytes, layout, i, points.data(), "fuzz.pc2");
    }
  } catch (const snag::InputError&) {
  }
  return 0;
}
