// One named object of a scene: its triangles and unique edges. Positions live
// in frames, not here: topology is the same in every frame.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "libcd/scene/mesh.hpp"

namespace snag {

/// How an object's vertices relate to the file's when coincident file
/// vertices were welded into one (io/vertex_weld.hpp). Both lists are empty
/// when the object's vertex ids are the file's own.
struct VertexWeld {
  std::string method = "none";       ///< "none", "exact" or "distance D" (D in scene units)
  std::vector<Index> file_ids;        ///< #V: the file id of each vertex, the smallest of those welded into it
  std::vector<Index> vertex_of_file;  ///< #file vertices: the vertex each file vertex became
};

struct Object {
  std::string name;
  Index vertex_count = 0;
  std::vector<Triangle> triangles;  ///< #F by 3 vertex ids into this object
  std::vector<Edge> edges;          ///< #E unique edges, sorted, each (lo, hi)
  VertexWeld weld;                  ///< file ids of the vertices; reports name vertices by them
};

/// The id the file gives vertex v of `object` (v itself unless welded).
inline Index file_vertex_id(const Object& object, Index v) {
  return object.weld.file_ids.empty() ? v : object.weld.file_ids[v];
}
/// The number of vertices the file has for `object` (vertex_count unless welded).
inline std::size_t file_vertex_count(const Object& object) {
  return object.weld.vertex_of_file.empty() ? object.vertex_count : object.weld.vertex_of_file.size();
}
/// The vertex that file vertex `file_id` (< file_vertex_count) became.
inline Index vertex_of_file_vertex(const Object& object, Index file_id) {
  return object.weld.vertex_of_file.empty() ? file_id : object.weld.vertex_of_file[file_id];
}

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
