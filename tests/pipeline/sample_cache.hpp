// The bundled cloth_ball sample (samples/README.md) opened as one cache: the
// cloth and the body from their point caches, one scene with global ids.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "io/open_cache.hpp"

namespace snag::test {

/// Opens samples/cloth_ball as two objects (cloth 961 vertices, body 114).
inline std::unique_ptr<FrameSource> open_sample_cache() {
  const std::string dir = std::string(SNAG_SOURCE_DIR) + "/samples/cloth_ball/";
  io::CacheOptions options;
  options.inputs.push_back({dir + "cloth.pc2", dir + "cloth_rest.obj", ""});
  options.inputs.push_back({dir + "body.pc2", dir + "body_rest.obj", ""});
  return io::open_cache(options);
}

/// Frame i's global positions.
inline std::vector<Vec3> read_positions(const FrameSource& source, std::size_t i) {
  std::vector<Vec3> x;
  source.read_frame(i, x);
  return x;
}

}  // namespace snag::test
