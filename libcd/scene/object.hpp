// One named object of a scene: its triangles and unique edges. Positions live
// in frames, not here: topology is the same in every frame.
#pragma once

#include <string>
#include <vector>

#include "libcd/scene/mesh.hpp"

namespace snag {

struct Object {
  std::string name;
  Index vertex_count = 0;
  std::vector<Triangle> triangles;  ///< #F by 3 vertex ids into this object
  std::vector<Edge> edges;          ///< #E unique edges, sorted, each (lo, hi)
};

/// Builds an object and its sorted unique edge list.
/// Asserts that every id is < vertex_count (readers check this first and throw).
Object make_object(std::string name, Index vertex_count, std::vector<Triangle> triangles);

/// Edge statistics of a triangle mesh, for snag-info.
struct EdgeCounts {
  std::size_t boundary = 0;      ///< edges used by exactly one triangle
  std::size_t non_manifold = 0;  ///< edges used by three or more triangles
};
EdgeCounts count_edge_kinds(const Object& object);

}  // namespace snag
