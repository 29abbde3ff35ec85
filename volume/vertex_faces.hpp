// The faces around each vertex of a triangle mesh, to walk from face to face.
#pragma once

#include <cstddef>
#include <vector>

#include "libcd/scene/mesh.hpp"

namespace snag::volume {

/// Compressed lists: the faces of vertex v are faces[start[v] .. start[v + 1]).
struct VertexFaces {
  std::vector<std::size_t> start, faces;
};

/// Of `triangles` (#F by 3 ids < vertex_count).
VertexFaces vertex_faces(const std::vector<Triangle>& triangles, std::size_t vertex_count);

}  // namespace snag::volume
