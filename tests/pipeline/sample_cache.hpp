// The bundled cloth_ball sample (samples/README.md) opened as one cache: the
// cloth and the body from their point caches, one scene with global ids; and
// any cache laid out as it is (scripts/bake_cloth_cache.py writes them).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "io/open_cache.hpp"

namespace snag::test {

/// Opens `dir` (relative to the source tree, with a trailing slash) as two
/// objects: cloth.pc2 on cloth_rest.obj and body.pc2 on body_rest.obj.
inline std::unique_ptr<FrameSource> open_cloth_body_cache(const std::string& dir) {
  const std::string path = std::string(SNAG_SOURCE_DIR) + "/" + dir;
  io::CacheOptions options;
  options.inputs.push_back({path + "cloth.pc2", path + "cloth_rest.obj", ""});
  options.inputs.push_back({path + "body.pc2", path + "body_rest.obj", ""});
  return io::open_cache(options);
}

/// Opens samples/cloth_ball as two objects (cloth 961 vertices, body 114).
inline std::unique_ptr<FrameSource> open_sample_cache() { return open_cloth_body_cache("samples/cloth_ball/"); }

/// Frame i's global positions.
inline std::vector<Vec3> read_positions(const FrameSource& source, std::size_t i) {
  std::vector<Vec3> x;
  source.read_frame(i, x);
  return x;
}

}  // namespace snag::test
