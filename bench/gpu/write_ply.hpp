// Writes a triangle mesh as binary little-endian PLY (double positions, int
// ids), the format snag's reader (io/ply_reader.hpp) takes: for the refined
// cloth frames that bench/scan/scan_bench.py scans through snag-scan.
#pragma once

#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag::bench {

/// Writes `vertices` (#V) and `triangles` (#F, ids into vertices) to `path`.
/// Throws std::runtime_error naming the file when it cannot be written.
/// Note: assumes a little-endian host (x86-64, arm64), as the header says.
inline void write_binary_ply(const std::string& path, const std::vector<Vec3>& vertices,
                             const std::vector<Triangle>& triangles) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error(path + ": cannot create");
  out << "ply\nformat binary_little_endian 1.0\nelement vertex " << vertices.size()
      << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& v : vertices) {
    const double xyz[3] = {v.x, v.y, v.z};
    out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
  }
  for (const Triangle& t : triangles) {
    const unsigned char count = 3;
    const std::int32_t ids[3] = {static_cast<std::int32_t>(t[0]), static_cast<std::int32_t>(t[1]),
                                 static_cast<std::int32_t>(t[2])};
    out.write(reinterpret_cast<const char*>(&count), 1);
    out.write(reinterpret_cast<const char*>(ids), sizeof ids);
  }
  if (!out.flush()) throw std::runtime_error(path + ": write failed");
}

}  // namespace snag::bench
