// One frame of a per-frame mesh file as a reader returns it: positions exactly
// as read, triangles, and the named objects the file holds.
#pragma once

#include <string>
#include <vector>

#include "libcd/geometry/vec3.hpp"
#include "libcd/scene/mesh.hpp"

namespace snag::io {

/// A named object inside a mesh file: its vertices are a subset of the file's,
/// listed in file order; its triangles use local ids into that subset.
struct MeshObject {
  std::string name;
  std::vector<Index> vertices;      ///< file vertex ids, ascending (local id = position here)
  std::vector<Triangle> triangles;  ///< local vertex ids
};

/// A whole file: all of its vertices, and its objects (at least one when the
/// file has triangles; files without object names give one object named after
/// the file's stem).
struct MeshData {
  std::vector<Vec3> positions;  ///< every vertex of the file, in file order
  std::vector<MeshObject> objects;
};

}  // namespace snag::io
