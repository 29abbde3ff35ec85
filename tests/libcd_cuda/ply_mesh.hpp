// A tiny reader of the binary PLY meshes in the reference data (vertex x, y, z
// as float or double; faces as a list of int or uint vertex ids), for the CUDA
// tests only; polygons are fan-triangulated.
#pragma once

#include <string>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag::test {

struct PlyMesh {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
};

/// Reads a binary (big- or little-endian) PLY file. Throws std::runtime_error
/// on a missing file, an unsupported layout, or a truncated body.
PlyMesh read_binary_ply(const std::string& path);

}  // namespace snag::test
